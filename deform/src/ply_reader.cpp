// PLY reading: the header is parsed first (ply_header.cpp), then one generic body walker runs
// over either an ascii or a binary value source. Both sources answer the same questions
// ("next scalar", "next list length", ...), so vertex, face and skipping logic exist once.

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <iterator>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "coordinate_range.hpp"
#include "file_bytes.hpp"
#include "number_text.hpp"
#include "ply_header.hpp"
#include "sculpt/deform/model_io.hpp"
#include "text_scanner.hpp"

namespace sculpt::deform {
namespace {

// Where each vertex property goes.
enum class Target : std::uint8_t { kSkip, kX, kY, kZ, kNx, kNy, kNz, kRed, kGreen, kBlue, kAlpha };

struct TargetName {
  std::string_view name;
  Target target;
};

// Some older writers call the colours "diffuse_red" and so on; both spellings are accepted.
constexpr TargetName kTargetNames[] = {
    {"x", Target::kX},
    {"y", Target::kY},
    {"z", Target::kZ},
    {"nx", Target::kNx},
    {"ny", Target::kNy},
    {"nz", Target::kNz},
    {"red", Target::kRed},
    {"green", Target::kGreen},
    {"blue", Target::kBlue},
    {"alpha", Target::kAlpha},
    {"diffuse_red", Target::kRed},
    {"diffuse_green", Target::kGreen},
    {"diffuse_blue", Target::kBlue},
    {"diffuse_alpha", Target::kAlpha},
};

constexpr const char* kTargetLabel[] = {"", "x", "y", "z", "nx", "ny", "nz", "red", "green", "blue", "alpha"};

// How the vertex element maps onto the model.
struct VertexPlan {
  std::vector<Target> targets;  // one per vertex property
  bool normals = false;
  bool colors = false;
  bool alpha = false;
};

// "3 vertices", "12 faces", "2 'edge' elements": used in truncation messages.
std::string count_of(std::uint64_t n, const std::string& element) {
  const std::string number = std::to_string(n);
  if (element == "vertex") return number + (n == 1 ? " vertex" : " vertices");
  if (element == "face") return number + (n == 1 ? " face" : " faces");
  return number + " " + quoted(element) + (n == 1 ? " element" : " elements");
}

VertexPlan plan_vertices(const PlyElement& vertex, const std::string& name) {
  auto fail = [&](const std::string& problem) { throw ModelFileError(name, line_where(vertex.line), problem); };
  VertexPlan plan;
  plan.targets.assign(vertex.properties.size(), Target::kSkip);
  bool seen[std::size(kTargetLabel)] = {};
  for (std::size_t i = 0; i < vertex.properties.size(); ++i) {
    const PlyProperty& property = vertex.properties[i];
    for (const TargetName& t : kTargetNames) {
      if (property.name != t.name) continue;
      const auto slot = static_cast<std::size_t>(t.target);
      if (property.is_list) fail("vertex property " + quoted(property.name) + " is a list");
      if (seen[slot]) fail("two vertex properties give " + quoted(kTargetLabel[slot]));
      seen[slot] = true;
      plan.targets[i] = t.target;
    }
  }
  auto all_or_none = [&](std::initializer_list<Target> group, bool required) {
    std::size_t present = 0;
    for (Target t : group) present += seen[static_cast<std::size_t>(t)] ? 1 : 0;
    if (present == group.size()) return true;
    if (present == 0 && !required) return false;
    for (Target t : group) {
      if (!seen[static_cast<std::size_t>(t)]) {
        fail("element 'vertex' has no property " + quoted(kTargetLabel[static_cast<std::size_t>(t)]));
      }
    }
    return false;
  };
  all_or_none({Target::kX, Target::kY, Target::kZ}, true);
  plan.normals = all_or_none({Target::kNx, Target::kNy, Target::kNz}, false);
  plan.colors = all_or_none({Target::kRed, Target::kGreen, Target::kBlue}, false);
  plan.alpha = seen[static_cast<std::size_t>(Target::kAlpha)];
  return plan;
}

// Colours. 8-bit integer types are taken as they are (a negative char clamps to 0). Wider
// integer types are clamped to 0..255, not rescaled from their full range: a header cannot say
// whether its "ushort red" spans 0..255 or 0..65535, and clamping keeps the 0..255 case exact.
// float/double colours are taken as 0..1 and scaled to 0..255 with rounding (NaN becomes 0).
std::uint8_t to_color(PlyType type, double value) {
  if (!ply_type_is_integer(type)) value *= 255.0;
  if (!(value > 0.0)) return 0;  // also catches NaN
  if (value >= 255.0) return 255;
  return static_cast<std::uint8_t>(std::lround(value));
}

void store(PointModel& m, Target target, PlyType type, std::size_t i, double value) {
  switch (target) {
    case Target::kSkip: break;
    case Target::kX: m.x[i] = static_cast<float>(value); break;
    case Target::kY: m.y[i] = static_cast<float>(value); break;
    case Target::kZ: m.z[i] = static_cast<float>(value); break;
    case Target::kNx: m.nx[i] = static_cast<float>(value); break;
    case Target::kNy: m.ny[i] = static_cast<float>(value); break;
    case Target::kNz: m.nz[i] = static_cast<float>(value); break;
    case Target::kRed: m.red[i] = to_color(type, value); break;
    case Target::kGreen: m.green[i] = to_color(type, value); break;
    case Target::kBlue: m.blue[i] = to_color(type, value); break;
    case Target::kAlpha: m.alpha[i] = to_color(type, value); break;
  }
}

// The name of the first non-finite position component of vertex i, or nullptr. Normals are
// not checked here: a non-finite normal is a missing one (scanners write NaN where they could
// not estimate it), which check_normals() re-estimates or refuses as the caller asks.
const char* non_finite_component(const PointModel& m, std::size_t i) {
  if (!std::isfinite(m.x[i])) return "x";
  if (!std::isfinite(m.y[i])) return "y";
  if (!std::isfinite(m.z[i])) return "z";
  return nullptr;
}

// ---------------------------------------------------------------------------------------
// Binary values: memcpy, then reverse the bytes when the file's byte order is not ours.

template <typename T>
T load(const char* p, bool swap) {
  unsigned char raw[sizeof(T)];
  std::memcpy(raw, p, sizeof(T));
  if (swap) std::reverse(raw, raw + sizeof(T));
  T value;
  std::memcpy(&value, raw, sizeof(T));
  return value;
}

double load_real(const char* p, PlyType type, bool swap) {
  switch (type) {
    case PlyType::kInt8: return load<std::int8_t>(p, swap);
    case PlyType::kUint8: return load<std::uint8_t>(p, swap);
    case PlyType::kInt16: return load<std::int16_t>(p, swap);
    case PlyType::kUint16: return load<std::uint16_t>(p, swap);
    case PlyType::kInt32: return load<std::int32_t>(p, swap);
    case PlyType::kUint32: return load<std::uint32_t>(p, swap);
    case PlyType::kFloat32: return load<float>(p, swap);
    case PlyType::kFloat64: return load<double>(p, swap);
  }
  return 0.0;
}

// Only called for integer types (the header parser and the face plan make sure).
std::int64_t load_integer(const char* p, PlyType type, bool swap) {
  switch (type) {
    case PlyType::kInt8: return load<std::int8_t>(p, swap);
    case PlyType::kUint8: return load<std::uint8_t>(p, swap);
    case PlyType::kInt16: return load<std::int16_t>(p, swap);
    case PlyType::kUint16: return load<std::uint16_t>(p, swap);
    case PlyType::kInt32: return load<std::int32_t>(p, swap);
    case PlyType::kUint32: return load<std::uint32_t>(p, swap);
    case PlyType::kFloat32:
    case PlyType::kFloat64: break;
  }
  return 0;
}

class BinarySource {
 public:
  BinarySource(std::string_view bytes, std::size_t offset, bool swap, const std::string& name)
      : bytes_(bytes), pos_(offset), swap_(swap), name_(name) {}

  /// Starts an element, first making sure the bytes left can hold its declared count, so a
  /// lying header is refused before anything is allocated for it.
  void begin_element(const PlyElement& element) {
    element_ = &element;
    begin_instance(0);
    const std::size_t min_size = element.min_binary_size();
    if (min_size == 0) return;
    const std::uint64_t at_most = remaining() / min_size;
    if (element.count <= at_most) return;
    if (element.fixed_size()) {
      // Every instance has the same size, so the complete ones can be counted exactly.
      index_ = at_most;
      instance_start_ = pos_ + static_cast<std::size_t>(at_most) * min_size;
      truncated();
    }
    fail("body truncated: expected " + count_of(element.count, element.name) + ", but the " +
         std::to_string(remaining()) + " bytes left can hold at most " + std::to_string(at_most));
  }
  void begin_instance(std::uint64_t index) {
    index_ = index;
    instance_start_ = pos_;
  }
  void end_instance() {}

  double scalar(const PlyProperty& property) {
    const char* p = take(ply_type_size(property.type));
    return load_real(p, property.type, swap_);
  }
  void skip_scalar(const PlyProperty& property) { take(ply_type_size(property.type)); }

  std::uint64_t list_length(const PlyProperty& property) {
    const char* p = take(ply_type_size(property.count_type));
    const std::int64_t length = load_integer(p, property.count_type, swap_);
    if (length < 0) {
      fail("negative length " + std::to_string(length) + " for list " + quoted(property.name));
    }
    // Checking the whole list against the bytes left keeps skipping it O(1) and lets the
    // caller trust the length.
    if (static_cast<std::uint64_t>(length) > remaining() / ply_type_size(property.type)) {
      truncated();
    }
    return static_cast<std::uint64_t>(length);
  }
  std::int64_t list_index(const PlyProperty& property) {
    return load_integer(take(ply_type_size(property.type)), property.type, swap_);
  }
  void skip_list(const PlyProperty& property, std::uint64_t length) {
    // list_length made sure the items are there.
    pos_ += static_cast<std::size_t>(length) * ply_type_size(property.type);
  }

  /// Skips all instances of an element whose contents the model does not need.
  void skip_element(const PlyElement& element) {
    begin_element(element);
    if (element.fixed_size()) {
      pos_ += static_cast<std::size_t>(element.count) * element.min_binary_size();  // checked
      return;
    }
    for (std::uint64_t i = 0; i < element.count; ++i) {
      begin_instance(i);
      for (const PlyProperty& property : element.properties) {
        if (property.is_list) {
          skip_list(property, list_length(property));
        } else {
          skip_scalar(property);
        }
      }
    }
  }

  /// Bytes after the last element are allowed: some writers end binary files with a newline.
  void end_body() const {}

  std::string instance_where() const { return "byte offset " + std::to_string(instance_start_); }

  [[noreturn]] void fail(const std::string& problem) const { throw ModelFileError(name_, instance_where(), problem); }

 private:
  std::size_t remaining() const { return bytes_.size() - pos_; }

  const char* take(std::size_t size) {
    if (size > remaining()) truncated();
    const char* p = bytes_.data() + pos_;
    pos_ += size;
    return p;
  }

  [[noreturn]] void truncated() const {
    fail("body truncated: expected " + count_of(element_->count, element_->name) + ", read " + std::to_string(index_) +
         " (the file ends at byte " + std::to_string(bytes_.size()) + ")");
  }

  std::string_view bytes_;
  std::size_t pos_;
  bool swap_;
  const std::string& name_;
  const PlyElement* element_ = nullptr;
  std::uint64_t index_ = 0;
  std::size_t instance_start_ = 0;
};

// ---------------------------------------------------------------------------------------
// Ascii values: one element instance per line, whitespace-separated numbers.

class AsciiSource {
 public:
  AsciiSource(std::string_view bytes, const PlyHeader& header, const std::string& name)
      : scanner_(bytes, header.body_offset, header.body_first_line), name_(name) {}

  /// Starts an element, first making sure the text left can hold its declared count: each
  /// instance needs at least one character per value, a separator between values and a line
  /// end (the last line may lack it). A lying header is refused before anything is allocated.
  void begin_element(const PlyElement& element) {
    element_ = &element;
    const std::size_t per_instance = 2 * element.min_ascii_values();
    if (per_instance == 0) return;
    const std::uint64_t at_most = (scanner_.remaining() + 1) / per_instance;
    if (element.count > at_most) {
      throw ModelFileError(name_, line_where(scanner_.next_line_number()),
                           "body truncated: expected " + count_of(element.count, element.name) + ", but the " +
                               std::to_string(scanner_.remaining()) + " bytes left can hold at most " +
                               std::to_string(at_most));
    }
  }

  void begin_instance(std::uint64_t index) {
    index_ = index;
    values_used_ = 0;
    std::string_view line;
    // Blank lines are not in the spec but turn up at the end of hand-edited files.
    while (scanner_.next_line(line)) {
      if (!is_blank_line(line)) {
        cursor_ = TokenCursor(line);
        return;
      }
    }
    throw ModelFileError(
        name_, line_where(scanner_.next_line_number()),
        "body truncated: expected " + count_of(element_->count, element_->name) + ", read " + std::to_string(index));
  }

  void end_instance() {
    if (!cursor_.at_end()) {
      fail("too many values for " + instance_name() + ": expected " + std::to_string(values_used_) +
           ", the line has more");
    }
  }

  double scalar(const PlyProperty& property) {
    const std::string_view token = next_token(property.name);
    if (property.type == PlyType::kFloat32) {
      // Parse floats as float: going through double could round twice and break the exact
      // round trip of the shortest-digits text our writer produces.
      float value = 0.0F;
      if (!parse_float(token, value)) not_a_number(token, property.name);
      return value;
    }
    double value = 0.0;
    if (!parse_double(token, value)) not_a_number(token, property.name);
    return value;
  }
  void skip_scalar(const PlyProperty& property) { scalar(property); }

  std::uint64_t list_length(const PlyProperty& property) {
    const std::string_view token = next_token(property.name);
    std::int64_t length = 0;
    if (!parse_int64(token, length)) {
      fail(quoted(token) + " is not an integer list length (list " + quoted(property.name) + " of " + instance_name() +
           ")");
    }
    if (length < 0) {
      fail("negative length " + std::to_string(length) + " for list " + quoted(property.name));
    }
    return static_cast<std::uint64_t>(length);
  }
  std::int64_t list_index(const PlyProperty& property) {
    const std::string_view token = next_token(property.name);
    std::int64_t value = 0;
    if (!parse_int64(token, value)) {
      fail(quoted(token) + " is not an integer (list " + quoted(property.name) + " of " + instance_name() + ")");
    }
    return value;
  }
  void skip_list(const PlyProperty& property, std::uint64_t length) {
    // Every item needs a token on this line, so this loop ends with the line at the latest.
    for (std::uint64_t i = 0; i < length; ++i) scalar(property);
  }

  void skip_element(const PlyElement& element) {
    begin_element(element);
    for (std::uint64_t i = 0; i < element.count; ++i) {
      begin_instance(i);
      for (const PlyProperty& property : element.properties) {
        if (property.is_list) {
          skip_list(property, list_length(property));
        } else {
          skip_scalar(property);
        }
      }
      end_instance();
    }
  }

  /// Text after the last declared element is refused, not ignored: it is a header that
  /// declares fewer elements than the file holds, and the rest of the model would be lost
  /// without a word. Blank lines and "comment" lines are allowed.
  void end_body() {
    std::string_view line;
    while (scanner_.next_line(line)) {
      TokenCursor cursor(line);
      std::string_view first;
      if (!cursor.next(first) || first == "comment") continue;
      fail("data after the declared elements, starting with " + quoted(first) +
           " (the header declares fewer elements than the file holds)");
    }
  }

  std::string instance_where() const { return line_where(scanner_.line_number()); }

  [[noreturn]] void fail(const std::string& problem) const { throw ModelFileError(name_, instance_where(), problem); }

 private:
  std::string instance_name() const {
    const std::string what =
        element_->name == "vertex" || element_->name == "face" ? element_->name : quoted(element_->name) + " element";
    return what + " " + std::to_string(index_);
  }

  std::string_view next_token(const std::string& property) {
    std::string_view token;
    if (!cursor_.next(token)) {
      fail("too few values for " + instance_name() + ": the line ends after " + std::to_string(values_used_) +
           " values, before " + quoted(property));
    }
    ++values_used_;
    return token;
  }

  [[noreturn]] void not_a_number(std::string_view token, const std::string& property) const {
    // A header line below end_header is a common hand-editing slip; name it as such.
    if (values_used_ == 1 &&
        (token == "property" || token == "element" || token == "comment" || token == "end_header")) {
      fail("header line " + quoted(token) + " after end_header");
    }
    fail(quoted(token) + " is not a number (property " + quoted(property) + " of " + instance_name() + ")");
  }

  TextScanner scanner_;
  TokenCursor cursor_{std::string_view{}};
  const std::string& name_;
  const PlyElement* element_ = nullptr;
  std::uint64_t index_ = 0;
  std::size_t values_used_ = 0;
};

// ---------------------------------------------------------------------------------------
// The body walker, shared by both sources.

template <typename Source>
void read_vertices(Source& source, const PlyElement& vertex, const VertexPlan& plan, PointModel& model) {
  source.begin_element(vertex);
  const auto count = static_cast<std::size_t>(vertex.count);
  model.resize(count, plan.normals, plan.colors, plan.alpha);
  for (std::size_t i = 0; i < count; ++i) {
    source.begin_instance(i);
    for (std::size_t k = 0; k < vertex.properties.size(); ++k) {
      const PlyProperty& property = vertex.properties[k];
      if (property.is_list) {
        source.skip_list(property, source.list_length(property));
      } else {
        store(model, plan.targets[k], property.type, i, source.scalar(property));
      }
    }
    source.end_instance();
    if (const char* bad = non_finite_component(model, i)) {
      source.fail("non-finite " + quoted(bad) + " in vertex " + std::to_string(i));
    }
    const std::string range = coordinate_range_problem(model.x[i], model.y[i], model.z[i], "vertex", i);
    if (!range.empty()) source.fail(range);
  }
}

template <typename Source>
void read_faces(Source& source, const PlyElement& face, std::size_t index_property, std::uint64_t vertex_count,
                std::size_t body_size, PointModel& model) {
  source.begin_element(face);
  // Most faces are triangles; reserve for that, but never more than the bytes could hold
  // (a lying face count must not allocate gigabytes).
  const std::uint64_t likely = std::min<std::uint64_t>(face.count, body_size / 4);
  model.triangles.reserve(static_cast<std::size_t>(likely) * 3);
  std::vector<std::uint32_t> polygon;
  for (std::uint64_t f = 0; f < face.count; ++f) {
    source.begin_instance(f);
    for (std::size_t k = 0; k < face.properties.size(); ++k) {
      const PlyProperty& property = face.properties[k];
      if (k == index_property) {
        const std::uint64_t length = source.list_length(property);
        polygon.clear();
        for (std::uint64_t j = 0; j < length; ++j) {
          const std::int64_t index = source.list_index(property);
          if (index < 0 || static_cast<std::uint64_t>(index) >= vertex_count) {
            source.fail("face " + std::to_string(f) + " refers to vertex " + std::to_string(index) +
                        ", but there are only " + std::to_string(vertex_count) + " vertices");
          }
          polygon.push_back(static_cast<std::uint32_t>(index));
        }
      } else if (property.is_list) {
        source.skip_list(property, source.list_length(property));
      } else {
        source.skip_scalar(property);
      }
    }
    source.end_instance();
    // Fan the polygon from its first corner; faces with fewer than 3 corners carry no area
    // and are dropped rather than refused.
    for (std::size_t j = 1; j + 1 < polygon.size(); ++j) {
      model.triangles.insert(model.triangles.end(), {polygon[0], polygon[j], polygon[j + 1]});
    }
  }
}

// The face element's index list, if it has one the model can use.
std::optional<std::size_t> face_index_property(const PlyElement& face, const std::string& name) {
  for (std::string_view list_name : {"vertex_indices", "vertex_index"}) {
    const auto k = face.find(list_name);
    if (!k || !face.properties[*k].is_list) continue;
    if (!ply_type_is_integer(face.properties[*k].type)) {
      throw ModelFileError(name, line_where(face.line),
                           "face list " + quoted(list_name) + " has non-integer item type " +
                               quoted(ply_type_name(face.properties[*k].type)));
    }
    return k;
  }
  return std::nullopt;
}

template <typename Source>
void read_body(Source& source, const PlyHeader& header, std::size_t file_size, const std::string& name,
               PointModel& model) {
  const PlyElement* vertex = nullptr;
  for (const PlyElement& element : header.elements) {
    if (element.name == "vertex") vertex = &element;
  }
  if (vertex == nullptr) {
    throw ModelFileError(name, line_where(header.end_header_line), "no 'vertex' element");
  }
  const VertexPlan plan = plan_vertices(*vertex, name);
  // Triangles hold 32-bit indices.
  if (vertex->count > std::numeric_limits<std::uint32_t>::max()) {
    throw ModelFileError(name, line_where(vertex->line), "too many vertices: " + std::to_string(vertex->count));
  }

  for (const PlyElement& element : header.elements) {
    if (&element == vertex) {
      read_vertices(source, element, plan, model);
      continue;
    }
    if (element.properties.empty() || element.count == 0) continue;  // occupies no bytes
    std::optional<std::size_t> indices;
    if (element.name == "face") indices = face_index_property(element, name);
    if (indices) {
      read_faces(source, element, *indices, vertex->count, file_size - header.body_offset, model);
    } else {
      source.skip_element(element);
    }
  }
  source.end_body();
}

}  // namespace

PointModel read_ply_from_buffer(std::string_view bytes, const std::string& name_for_errors) {
  const PlyHeader header = parse_ply_header(bytes, name_for_errors);
  PointModel model;
  if (header.encoding == PlyEncoding::kAscii) {
    AsciiSource source(bytes, header, name_for_errors);
    read_body(source, header, bytes.size(), name_for_errors, model);
  } else {
    const bool file_little = header.encoding == PlyEncoding::kBinaryLittleEndian;
    const bool host_little = std::endian::native == std::endian::little;
    BinarySource source(bytes, header.body_offset, file_little != host_little, name_for_errors);
    read_body(source, header, bytes.size(), name_for_errors, model);
  }
  return model;
}

PointModel read_ply(const std::string& path) { return read_ply_from_buffer(read_file_bytes(path), path); }

}  // namespace sculpt::deform
