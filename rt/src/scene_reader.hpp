#pragma once
// Strict reading of one TOML table of a scene: every key looked up by name, every unknown key,
// wrong type or bad value reported as a SceneError with its full dotted key and its position.
// Private to rt (it includes toml++, which is slow to compile).

#include <cstdint>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <toml++/toml.h>

#include "sculpt/deform/vec3.hpp"
#include "sculpt/rt/scene.hpp"

namespace sculpt::rt::scene_detail {

/// The file name every message starts with.
struct Context {
  std::string file;
};

[[noreturn]] void fail(const Context& context, const toml::source_position& where, const std::string& key,
                       const std::string& problem);

/// A number as every message prints it (base::number_text, %g: "0.5", "3e+07", "1e-09").
std::string show(double value);
/// "string", "integer", "float", "boolean", "array", "table", "date", "time", "date-time".
std::string_view type_name(const toml::node& node);
/// "'a', 'b' or 'c'".
std::string one_of(std::initializer_list<std::string_view> names);
std::string one_of(const std::vector<std::string_view>& names);

/// A number (integer or float) that must be finite; `key` names it in messages.
double as_number(const Context& context, const toml::node& node, const std::string& key);
/// [x, y, z] of finite numbers.
deform::Vec3 as_vec3(const Context& context, const toml::node& node, const std::string& key);

/// One table of the scene, which may be absent (then every lookup finds nothing and messages
/// point at where the table would have been declared).
class Section {
 public:
  Section(const Context& context, const toml::table* table, std::string path, toml::source_position where);

  /// Fails on the first key (in file order) that is not in `keys`, naming it in full.
  void allow(std::initializer_list<std::string_view> keys) const;

  bool present() const { return table_ != nullptr; }
  bool has(std::string_view key) const { return node(key) != nullptr; }
  const toml::node* node(std::string_view key) const;
  /// The position of `key` in the file, or of this table when the key is absent.
  toml::source_position where(std::string_view key) const;
  toml::source_position where() const { return where_; }
  /// "glove.sim" + "rate_hz" -> "glove.sim.rate_hz".
  std::string key(std::string_view key) const;
  const std::string& path() const { return path_; }
  const Context& context() const { return *context_; }

  [[noreturn]] void fail(std::string_view key, const std::string& problem) const;
  /// "unknown value 'x'; expected 'a', 'b' or 'c'".
  [[noreturn]] void unknown_value(std::string_view key, const std::string& value,
                                  const std::vector<std::string_view>& allowed) const;
  void check(bool ok, std::string_view key, const std::string& problem) const {
    if (!ok) fail(key, problem);
  }
  /// Fails unless `key` is present.
  void require(std::string_view key, const std::string& why = {}) const;

  /// The sub-table `key` (absent when missing), with its own unknown-key check.
  Section table(std::string_view key, std::initializer_list<std::string_view> keys) const;

  std::optional<double> number(std::string_view key) const;
  std::optional<std::int64_t> integer(std::string_view key) const;
  std::optional<bool> boolean(std::string_view key) const;
  std::optional<std::string> string(std::string_view key) const;
  std::optional<deform::Vec3> vec3(std::string_view key) const;
  const toml::array* array(std::string_view key) const;

  /// A number within [lo, hi] (either end open when the flag says so). `note`, when given, ends
  /// the message in parentheses: the unit and what the bound means ("ms: at most an hour").
  std::optional<double> number_in(std::string_view key, double lo, bool lo_open, double hi, bool hi_open,
                                  std::string_view note = {}) const;
  /// A non-negative number (zero allowed) or a positive one.
  std::optional<double> non_negative(std::string_view key) const;
  std::optional<double> positive(std::string_view key) const;
  /// An integer within [lo, hi].
  std::optional<std::int64_t> integer_in(std::string_view key, std::int64_t lo, std::int64_t hi) const;

  /// One of the named values.
  template <typename E>
  std::optional<E> choice(std::string_view key, std::initializer_list<std::pair<std::string_view, E>> values) const {
    const auto text = string(key);
    if (!text) return std::nullopt;
    for (const auto& [name, value] : values) {
      if (*text == name) return value;
    }
    std::vector<std::string_view> names;
    for (const auto& entry : values) names.push_back(entry.first);
    unknown_value(key, *text, names);
  }

 private:
  const Context* context_;
  const toml::table* table_;
  std::string path_;
  toml::source_position where_;
};

}  // namespace sculpt::rt::scene_detail
