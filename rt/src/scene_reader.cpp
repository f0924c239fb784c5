#include "scene_reader.hpp"

#include "sculpt/base/number_text.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace sculpt::rt::scene_detail {

void fail(const Context& context, const toml::source_position& where, const std::string& key,
          const std::string& problem) {
  // A table toml++ created implicitly (the root, or "glove" for a lone [glove.sim]) may have no
  // position of its own; the top of the file is still a place an editor can jump to.
  const int line = where.line > 0 ? static_cast<int>(where.line) : 1;
  const int column = where.line > 0 ? static_cast<int>(where.column) : 1;
  throw SceneError(context.file, line, column, key, problem);
}

std::string show(double value) { return base::number_text(value); }

std::string_view type_name(const toml::node& node) {
  switch (node.type()) {
    case toml::node_type::string: return "string";
    case toml::node_type::integer: return "integer";
    case toml::node_type::floating_point: return "float";
    case toml::node_type::boolean: return "boolean";
    case toml::node_type::array: return "array";
    case toml::node_type::table: return "table";
    case toml::node_type::date: return "date";
    case toml::node_type::time: return "time";
    case toml::node_type::date_time: return "date-time";
    case toml::node_type::none: break;
  }
  return "nothing";
}

std::string one_of(const std::vector<std::string_view>& names) {
  // Appended piece by piece: GCC 12 warns falsely (-Wrestrict) on "'" + std::string + "'".
  std::string text;
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (i > 0) text += i + 1 == names.size() ? " or " : ", ";
    text += '\'';
    text += names[i];
    text += '\'';
  }
  return text;
}

std::string one_of(std::initializer_list<std::string_view> names) {
  return one_of(std::vector<std::string_view>(names));
}

double as_number(const Context& context, const toml::node& node, const std::string& key) {
  double value = 0.0;
  if (const auto* i = node.as_integer()) {
    value = static_cast<double>(i->get());
  } else if (const auto* f = node.as_floating_point()) {
    value = f->get();
  } else {
    fail(context, node.source().begin, key, "expected a number, got " + std::string(type_name(node)));
  }
  // TOML spells nan and inf; no setting of a scene means either.
  if (!std::isfinite(value)) fail(context, node.source().begin, key, "must be finite, got " + show(value));
  return value;
}

deform::Vec3 as_vec3(const Context& context, const toml::node& node, const std::string& key) {
  const auto* array = node.as_array();
  if (array == nullptr) {
    fail(context, node.source().begin, key, "expected [x, y, z], got " + std::string(type_name(node)));
  }
  if (array->size() != 3) {
    fail(context, node.source().begin, key, "expected [x, y, z], got " + std::to_string(array->size()) + " elements");
  }
  deform::Vec3 v;
  for (int i = 0; i < 3; ++i) {
    v[i] = as_number(context, *array->get(static_cast<std::size_t>(i)), key + "[" + std::to_string(i) + "]");
  }
  return v;
}

Section::Section(const Context& context, const toml::table* table, std::string path, toml::source_position where)
    : context_(&context), table_(table), path_(std::move(path)), where_(where) {
  if (table_ != nullptr && table_->source().begin.line > 0) where_ = table_->source().begin;
}

void Section::allow(std::initializer_list<std::string_view> keys) const {
  if (table_ == nullptr) return;
  for (const auto& [name, value] : *table_) {
    if (std::find(keys.begin(), keys.end(), name.str()) == keys.end()) {
      auto at = name.source().begin;
      if (at.line == 0) at = value.source().begin;
      scene_detail::fail(*context_, at, key(name.str()), "unknown key");
    }
  }
}

const toml::node* Section::node(std::string_view key) const { return table_ == nullptr ? nullptr : table_->get(key); }

toml::source_position Section::where(std::string_view key) const {
  if (table_ != nullptr) {
    const auto it = table_->find(key);
    if (it != table_->end()) {
      // The key's own position: its line, and the column an editor shows for it.
      if (it->first.source().begin.line > 0) return it->first.source().begin;
      if (it->second.source().begin.line > 0) return it->second.source().begin;
    }
  }
  return where_;
}

std::string Section::key(std::string_view key) const {
  if (path_.empty()) return std::string(key);
  return path_ + "." + std::string(key);
}

void Section::fail(std::string_view key, const std::string& problem) const {
  scene_detail::fail(*context_, where(key), this->key(key), problem);
}

void Section::unknown_value(std::string_view key, const std::string& value,
                            const std::vector<std::string_view>& allowed) const {
  std::string problem = "unknown value '";
  problem += value;
  problem += "'; expected ";
  problem += one_of(allowed);
  fail(key, problem);
}

void Section::require(std::string_view key, const std::string& why) const {
  if (has(key)) return;
  fail(key, why.empty() ? "missing required key" : "missing required key (" + why + ")");
}

Section Section::table(std::string_view key, std::initializer_list<std::string_view> keys) const {
  const toml::node* n = node(key);
  const toml::table* t = nullptr;
  if (n != nullptr) {
    t = n->as_table();
    if (t == nullptr) fail(key, "expected a table, got " + std::string(type_name(*n)));
  }
  Section section(*context_, t, this->key(key), where(key));
  section.allow(keys);
  return section;
}

std::optional<double> Section::number(std::string_view key) const {
  const toml::node* n = node(key);
  if (n == nullptr) return std::nullopt;
  if (!n->is_number()) fail(key, "expected a number, got " + std::string(type_name(*n)));
  const double value = n->is_integer() ? static_cast<double>(n->as_integer()->get()) : n->as_floating_point()->get();
  if (!std::isfinite(value)) fail(key, "must be finite, got " + show(value));
  return value;
}

std::optional<std::int64_t> Section::integer(std::string_view key) const {
  const toml::node* n = node(key);
  if (n == nullptr) return std::nullopt;
  if (!n->is_integer()) fail(key, "expected an integer, got " + std::string(type_name(*n)));
  return n->as_integer()->get();
}

std::optional<bool> Section::boolean(std::string_view key) const {
  const toml::node* n = node(key);
  if (n == nullptr) return std::nullopt;
  if (!n->is_boolean()) {
    fail(key, "expected a boolean (true or false), got " + std::string(type_name(*n)));
  }
  return n->as_boolean()->get();
}

std::optional<std::string> Section::string(std::string_view key) const {
  const toml::node* n = node(key);
  if (n == nullptr) return std::nullopt;
  if (!n->is_string()) fail(key, "expected a string, got " + std::string(type_name(*n)));
  const std::string& text = n->as_string()->get();
  // Every scene string is a path, a name or a URL, which the system cuts at a NUL: "x.txt\u0000.ply"
  // passed the .ply check and then wrote over x.txt.
  if (text.find('\0') != std::string::npos) {
    fail(key, "holds a NUL character (\\u0000) at position " + std::to_string(text.find('\0')) +
                  ": a path or name would end there");
  }
  return text;
}

std::optional<deform::Vec3> Section::vec3(std::string_view key) const {
  const toml::node* n = node(key);
  if (n == nullptr) return std::nullopt;
  if (!n->is_array()) fail(key, "expected [x, y, z], got " + std::string(type_name(*n)));
  return as_vec3(*context_, *n, this->key(key));
}

const toml::array* Section::array(std::string_view key) const {
  const toml::node* n = node(key);
  if (n == nullptr) return nullptr;
  if (!n->is_array()) fail(key, "expected an array, got " + std::string(type_name(*n)));
  return n->as_array();
}

std::optional<double> Section::number_in(std::string_view key, double lo, bool lo_open, double hi, bool hi_open,
                                         std::string_view note) const {
  const auto value = number(key);
  if (!value) return value;
  const bool above = lo_open ? *value > lo : *value >= lo;
  const bool below = hi_open ? *value < hi : *value <= hi;
  if (!above || !below) {
    std::string problem = "out of range: " + show(*value) + " is not in " + (lo_open ? "(" : "[") + show(lo) + ", " +
                          show(hi) + (hi_open ? ")" : "]");
    if (!note.empty()) {
      problem += " (";
      problem += note;
      problem += ')';
    }
    fail(key, problem);
  }
  return value;
}

std::optional<double> Section::non_negative(std::string_view key) const {
  const auto value = number(key);
  if (value && *value < 0.0) fail(key, "must be >= 0, got " + show(*value));
  return value;
}

std::optional<double> Section::positive(std::string_view key) const {
  const auto value = number(key);
  if (value && !(*value > 0.0)) fail(key, "must be > 0, got " + show(*value));
  return value;
}

std::optional<std::int64_t> Section::integer_in(std::string_view key, std::int64_t lo, std::int64_t hi) const {
  const auto value = integer(key);
  if (value && (*value < lo || *value > hi)) {
    fail(key, "out of range: " + std::to_string(*value) + " is not in [" + std::to_string(lo) + ", " +
                  std::to_string(hi) + "]");
  }
  return value;
}

}  // namespace sculpt::rt::scene_detail
