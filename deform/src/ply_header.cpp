// PLY header parsing: one line at a time, every problem reported with its line number.

#include "ply_header.hpp"

#include <array>
#include <string>
#include <vector>

#include "number_text.hpp"
#include "text_scanner.hpp"

namespace sculpt::deform {
namespace {

struct TypeName {
  std::string_view classic;  // always from a literal, so data() is NUL-terminated
  std::string_view sized;
  PlyType type;
  std::size_t size;
};

constexpr std::array<TypeName, 8> kTypeNames = {{
    {"char", "int8", PlyType::kInt8, 1},
    {"uchar", "uint8", PlyType::kUint8, 1},
    {"short", "int16", PlyType::kInt16, 2},
    {"ushort", "uint16", PlyType::kUint16, 2},
    {"int", "int32", PlyType::kInt32, 4},
    {"uint", "uint32", PlyType::kUint32, 4},
    {"float", "float32", PlyType::kFloat32, 4},
    {"double", "float64", PlyType::kFloat64, 8},
}};

// Tokens of one header line; header lines are short, so a small vector is fine here.
std::vector<std::string_view> split(std::string_view line) {
  std::vector<std::string_view> tokens;
  TokenCursor cursor(line);
  std::string_view token;
  while (cursor.next(token)) tokens.push_back(token);
  return tokens;
}

}  // namespace

std::size_t ply_type_size(PlyType type) { return kTypeNames[static_cast<std::size_t>(type)].size; }

bool ply_type_is_integer(PlyType type) { return type != PlyType::kFloat32 && type != PlyType::kFloat64; }

std::optional<PlyType> ply_type_from_name(std::string_view name) {
  for (const TypeName& t : kTypeNames) {
    if (name == t.classic || name == t.sized) return t.type;
  }
  return std::nullopt;
}

const char* ply_type_name(PlyType type) { return kTypeNames[static_cast<std::size_t>(type)].classic.data(); }

std::optional<std::size_t> PlyElement::find(std::string_view property_name) const {
  for (std::size_t i = 0; i < properties.size(); ++i) {
    if (properties[i].name == property_name) return i;
  }
  return std::nullopt;
}

bool PlyElement::fixed_size() const {
  for (const PlyProperty& p : properties) {
    if (p.is_list) return false;
  }
  return true;
}

std::size_t PlyElement::min_binary_size() const {
  std::size_t size = 0;
  for (const PlyProperty& p : properties) size += ply_type_size(p.is_list ? p.count_type : p.type);
  return size;
}

std::size_t PlyElement::min_ascii_values() const { return properties.size(); }

PlyHeader parse_ply_header(std::string_view bytes, const std::string& name) {
  TextScanner scanner(bytes);
  std::string_view line;
  // The magic must be the very first bytes: "ply" then a line end.
  if (!scanner.next_line(line) || line != "ply") {
    throw ModelFileError(name, line_where(1), "missing magic 'ply' at the start of the file");
  }
  auto fail = [&](const std::string& problem) {
    throw ModelFileError(name, line_where(scanner.line_number()), problem);
  };

  PlyHeader header;
  bool have_format = false;
  while (scanner.next_line(line)) {
    const std::vector<std::string_view> tokens = split(line);
    if (tokens.empty()) continue;  // not in the spec, but harmless
    const std::string_view keyword = tokens[0];
    // A header cut off mid-line would otherwise be reported as whatever the fragment
    // looks like ("unknown header keyword 'prop'").
    const bool unterminated = scanner.remaining() == 0 && bytes.back() != '\n';
    if (unterminated && keyword != "end_header") {
      fail("header truncated: the file ends inside the header");
    }
    if (keyword == "comment" || keyword == "obj_info") continue;
    if (keyword == "format") {
      if (have_format) fail("second format line");
      if (tokens.size() != 3) fail("format line needs an encoding and a version");
      if (tokens[1] == "ascii") {
        header.encoding = PlyEncoding::kAscii;
      } else if (tokens[1] == "binary_little_endian") {
        header.encoding = PlyEncoding::kBinaryLittleEndian;
      } else if (tokens[1] == "binary_big_endian") {
        header.encoding = PlyEncoding::kBinaryBigEndian;
      } else {
        fail("unknown format " + quoted(tokens[1]));
      }
      double version = 0.0;
      if (!parse_double(tokens[2], version) || version != 1.0) {
        fail("unsupported version " + quoted(tokens[2]) + " (only 1.0 is supported)");
      }
      have_format = true;
    } else if (keyword == "element") {
      if (tokens.size() != 3) fail("element line needs a name and a count");
      PlyElement element;
      element.name = std::string(tokens[1]);
      element.line = scanner.line_number();
      if (!parse_uint64(tokens[2], element.count)) {
        fail("bad element count " + quoted(tokens[2]) + " for element " + quoted(tokens[1]));
      }
      for (const PlyElement& other : header.elements) {
        if (other.name == element.name) fail("element " + quoted(element.name) + " declared twice");
      }
      header.elements.push_back(std::move(element));
    } else if (keyword == "property") {
      if (header.elements.empty()) fail("property before any element");
      PlyProperty property;
      if (tokens.size() >= 2 && tokens[1] == "list") {
        if (tokens.size() != 5) {
          fail("list property line needs a count type, an item type and a name");
        }
        const auto count_type = ply_type_from_name(tokens[2]);
        const auto item_type = ply_type_from_name(tokens[3]);
        if (!count_type) fail("unknown property type " + quoted(tokens[2]));
        if (!item_type) fail("unknown property type " + quoted(tokens[3]));
        if (!ply_type_is_integer(*count_type)) {
          fail("list count type " + quoted(tokens[2]) + " is not an integer type");
        }
        property.is_list = true;
        property.count_type = *count_type;
        property.type = *item_type;
        property.name = std::string(tokens[4]);
      } else {
        if (tokens.size() != 3) fail("property line needs a type and a name");
        const auto type = ply_type_from_name(tokens[1]);
        if (!type) fail("unknown property type " + quoted(tokens[1]));
        property.type = *type;
        property.name = std::string(tokens[2]);
      }
      PlyElement& element = header.elements.back();
      if (element.find(property.name)) {
        fail("property " + quoted(property.name) + " declared twice in element " + quoted(element.name));
      }
      element.properties.push_back(std::move(property));
    } else if (keyword == "end_header") {
      if (tokens.size() != 1) fail("unexpected text after end_header");
      if (!have_format) fail("no format line before end_header");
      header.end_header_line = scanner.line_number();
      header.body_offset = scanner.offset();
      header.body_first_line = scanner.next_line_number();
      return header;
    } else {
      fail("unknown header keyword " + quoted(keyword));
    }
  }
  throw ModelFileError(name, line_where(scanner.next_line_number()),
                       "header truncated: no end_header before the end of the file");
}

}  // namespace sculpt::deform
