// XYZ reading: one point per line, "x y z" or "x y z nx ny nz". The first point line decides
// which; a file that mixes the two is refused rather than guessed at.

#include <cmath>
#include <string>
#include <string_view>

#include "coordinate_range.hpp"
#include "file_bytes.hpp"
#include "number_text.hpp"
#include "sculpt/deform/model_io.hpp"
#include "text_scanner.hpp"

namespace sculpt::deform {
namespace {

constexpr const char* kColumnNames[] = {"x", "y", "z", "nx", "ny", "nz"};

}  // namespace

PointModel read_xyz_from_buffer(std::string_view text, const std::string& name_for_errors) {
  TextScanner scanner(text);
  auto fail = [&](const std::string& problem) {
    throw ModelFileError(name_for_errors, line_where(scanner.line_number()), problem);
  };
  PointModel model;
  std::size_t columns = 0;  // 3 or 6 once the first point is seen
  std::size_t first_point_line = 0;
  std::string_view line;
  while (scanner.next_line(line)) {
    line = strip_comment(line);
    if (is_blank_line(line)) continue;
    std::string_view tokens[6];
    std::size_t n = 0;
    TokenCursor cursor(line);
    std::string_view token;
    while (cursor.next(token)) {
      if (n < 6) tokens[n] = token;
      ++n;
    }
    if (columns == 0) {
      if (n != 3 && n != 6) {
        fail("expected 3 values (x y z) or 6 (x y z nx ny nz), found " + std::to_string(n));
      }
      columns = n;
      first_point_line = scanner.line_number();
    } else if (n != columns) {
      fail("expected " + std::to_string(columns) + " values like line " + std::to_string(first_point_line) +
           ", found " + std::to_string(n));
    }
    const std::size_t i = model.size();
    float v[6] = {};
    for (std::size_t k = 0; k < columns; ++k) {
      if (!parse_float(tokens[k], v[k])) {
        fail(quoted(tokens[k]) + " is not a number (" + kColumnNames[k] + " of point " + std::to_string(i) + ")");
      }
      // A non-finite normal is a missing one, for check_normals() to handle.
      if (k < 3 && !std::isfinite(v[k])) {
        fail(std::string("non-finite '") + kColumnNames[k] + "' in point " + std::to_string(i));
      }
    }
    const std::string range = coordinate_range_problem(v[0], v[1], v[2], "point", i);
    if (!range.empty()) fail(range);
    model.x.push_back(v[0]);
    model.y.push_back(v[1]);
    model.z.push_back(v[2]);
    if (columns == 6) {
      model.nx.push_back(v[3]);
      model.ny.push_back(v[4]);
      model.nz.push_back(v[5]);
    }
  }
  return model;
}

PointModel read_xyz(const std::string& path) { return read_xyz_from_buffer(read_file_bytes(path), path); }

}  // namespace sculpt::deform
