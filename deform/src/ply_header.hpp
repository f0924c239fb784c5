#pragma once
// The PLY header: element and property declarations, parsed and checked before any body
// byte is touched. Shared by the reader (which needs it all) and the writer (type names).

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "sculpt/deform/model_io.hpp"

namespace sculpt::deform {

/// The eight PLY numeric types.
enum class PlyType : std::uint8_t { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };

/// Bytes one value of `type` takes in a binary body.
std::size_t ply_type_size(PlyType type);
/// True for the six integer types.
bool ply_type_is_integer(PlyType type);
/// The type for a header name, accepting both spellings ("uchar" and "uint8"); nullopt if unknown.
std::optional<PlyType> ply_type_from_name(std::string_view name);
/// The classic header name ("float", "uchar", ...).
const char* ply_type_name(PlyType type);

/// One "property" line. For lists, `type` is the item type and `count_type` the length type.
struct PlyProperty {
  std::string name;
  PlyType type = PlyType::kFloat32;
  bool is_list = false;
  PlyType count_type = PlyType::kUint8;
};

/// One "element" line and the properties declared under it.
struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;
  std::size_t line = 0;  ///< header line of the declaration, for errors

  /// Index of the property called `name`, or nullopt.
  std::optional<std::size_t> find(std::string_view property_name) const;
  /// True when every property is a scalar, so every instance has the same size.
  bool fixed_size() const;
  /// Binary bytes of one instance when every list is empty (the exact size when fixed_size()).
  std::size_t min_binary_size() const;
  /// Ascii values one instance has at least (scalars plus list lengths).
  std::size_t min_ascii_values() const;
};

/// Everything the header says, plus where the body starts.
struct PlyHeader {
  PlyEncoding encoding = PlyEncoding::kAscii;
  std::vector<PlyElement> elements;
  std::size_t body_offset = 0;      ///< byte offset of the first body byte
  std::size_t body_first_line = 0;  ///< line number of the first body line (ascii errors)
  std::size_t end_header_line = 0;  ///< line number of "end_header"
};

/// Parses the header at the start of `bytes`. Throws ModelFileError naming `name`, the line
/// and the problem when the header is malformed.
PlyHeader parse_ply_header(std::string_view bytes, const std::string& name);

}  // namespace sculpt::deform
