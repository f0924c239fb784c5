// OFF reading (Geomview's Object File Format and its NOFF / COFF / STOFF variants).
// The format is line oriented in practice: one vertex or face per line, so optional trailing
// values (colours, texture coordinates) can be told apart from the next record.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "coordinate_range.hpp"
#include "file_bytes.hpp"
#include "number_text.hpp"
#include "sculpt/deform/model_io.hpp"
#include "text_scanner.hpp"

namespace sculpt::deform {
namespace {

// Which optional per-vertex values the header keyword announces ("[ST][C][N]OFF").
struct OffVariant {
  bool texture = false;
  bool colors = false;
  bool normals = false;
};

class OffParser {
 public:
  OffParser(std::string_view text, const std::string& name) : scanner_(text), name_(name) {}

  PointModel parse() {
    std::string_view line;
    if (!next_content_line(line)) fail_at(1, "empty file: missing 'OFF' header keyword");
    TokenCursor header(line);
    std::string_view keyword;
    header.next(keyword);
    const OffVariant variant = parse_keyword(keyword);

    // The counts are either on the keyword line ("OFF 8 6 12") or on the next content line.
    TokenCursor counts = header;
    if (header.at_end()) {
      if (!next_content_line(line)) {
        fail_at(scanner_.next_line_number(), "missing vertex and face counts");
      }
      counts = TokenCursor(line);
    }
    const std::size_t header_line = scanner_.line_number();
    const std::uint64_t vertex_count = parse_count(counts, "vertex");
    const std::uint64_t face_count = parse_count(counts, "face");
    std::string_view edges;
    if (counts.next(edges)) {  // the edge count is optional and unused, but must be a count
      std::uint64_t unused = 0;
      if (!parse_uint64(edges, unused)) fail("bad edge count " + quoted(edges));
      if (!counts.at_end()) fail("unexpected text after the vertex, face and edge counts");
    }
    // Each vertex line has at least "0 0 0": refuse counts the file cannot hold before
    // allocating for them.
    if (vertex_count > scanner_.remaining() / 5 || vertex_count > std::numeric_limits<std::uint32_t>::max()) {
      fail("vertex count " + std::to_string(vertex_count) + " is more than the file can hold");
    }

    PointModel model;
    read_vertices(variant, static_cast<std::size_t>(vertex_count), model);
    // Each face line has at least its corner count and a line end ("0\n"; the last line may
    // lack it): a face count the rest of the file cannot hold is refused before any reserve.
    if (face_count > (scanner_.remaining() + 1) / 2) {
      fail_at(header_line, "face count " + std::to_string(face_count) + " is more than the rest of the file can hold");
    }
    read_faces(face_count, model);
    refuse_trailing_data();
    return model;
  }

 private:
  // Skips blank and comment-only lines; returns the next line without its comment.
  bool next_content_line(std::string_view& line) {
    while (scanner_.next_line(line)) {
      line = strip_comment(line);
      if (!is_blank_line(line)) return true;
    }
    return false;
  }

  // Edges are counted in the header but never listed, so a content line after the last face
  // means the counts are short of what the file holds: refused rather than dropped unseen.
  void refuse_trailing_data() {
    std::string_view line;
    if (!next_content_line(line)) return;
    TokenCursor tokens(line);
    std::string_view first;
    tokens.next(first);
    fail("data after the declared vertices and faces, starting with " + quoted(first) +
         " (the header's counts are fewer than the file holds)");
  }

  OffVariant parse_keyword(std::string_view keyword) {
    OffVariant variant;
    std::string_view rest = keyword;
    auto take = [&rest](std::string_view prefix) {
      if (rest.substr(0, prefix.size()) != prefix) return false;
      rest.remove_prefix(prefix.size());
      return true;
    };
    variant.texture = take("ST");
    variant.colors = take("C");
    variant.normals = take("N");
    if (rest == "4OFF" || rest == "nOFF") {
      fail("unsupported OFF variant " + quoted(keyword) + " (only 3D is supported)");
    }
    if (rest != "OFF") fail("missing 'OFF' header keyword (found " + quoted(keyword) + ")");
    return variant;
  }

  std::uint64_t parse_count(TokenCursor& counts, const char* what) {
    std::string_view token;
    if (!counts.next(token)) fail(std::string("missing ") + what + " count");
    std::uint64_t value = 0;
    if (!parse_uint64(token, value)) fail(std::string("bad ") + what + " count " + quoted(token));
    return value;
  }

  float number(TokenCursor& tokens, const char* what, std::size_t index) {
    std::string_view token;
    if (!tokens.next(token)) {
      fail(std::string("too few values for vertex ") + std::to_string(index) + ": no " + what);
    }
    float value = 0.0F;
    if (!parse_float(token, value)) {
      fail(quoted(token) + " is not a number (" + what + " of vertex " + std::to_string(index) + ")");
    }
    return value;
  }

  void read_vertices(const OffVariant& variant, std::size_t count, PointModel& model) {
    model.resize(count, variant.normals, variant.colors);
    std::string_view line;
    for (std::size_t i = 0; i < count; ++i) {
      if (!next_content_line(line)) {
        fail_at(scanner_.next_line_number(),
                "file truncated: expected " + std::to_string(count) + " vertices, read " + std::to_string(i));
      }
      TokenCursor tokens(line);
      model.x[i] = number(tokens, "x", i);
      model.y[i] = number(tokens, "y", i);
      model.z[i] = number(tokens, "z", i);
      if (variant.normals) {
        model.nx[i] = number(tokens, "nx", i);
        model.ny[i] = number(tokens, "ny", i);
        model.nz[i] = number(tokens, "nz", i);
      }
      if (variant.colors) read_color(tokens, variant.texture, i, model);
      // Further values (texture coordinates, or colours in a file that says plain "OFF")
      // are ignored.
      check_finite(model, i);
    }
  }

  // Colours are "r g b [a]", either integers 0..255 or floats 0..1: a '.' or exponent in any
  // of them means floats. Any "s t" texture coordinates come after the colour. Alpha is
  // checked but dropped: OFF colours are for display and the model keeps rgb only.
  void read_color(TokenCursor& tokens, bool texture, std::size_t i, PointModel& model) {
    std::string_view values[6];
    std::size_t n = 0;
    std::string_view token;
    while (n < 6 && tokens.next(token)) values[n++] = token;
    if (texture && n >= 2) n -= 2;
    if (n < 3) fail("too few values for vertex " + std::to_string(i) + ": no colour");
    bool floats = false;
    for (std::size_t k = 0; k < n; ++k) {
      floats = floats || values[k].find_first_of(".eE") != std::string_view::npos;
    }
    std::uint8_t channel[4] = {};
    for (std::size_t k = 0; k < n && k < 4; ++k) {
      double v = 0.0;
      if (!parse_double(values[k], v)) {
        fail(quoted(values[k]) + " is not a number (colour of vertex " + std::to_string(i) + ")");
      }
      if (floats) v *= 255.0;
      channel[k] = !(v > 0.0) ? 0 : v >= 255.0 ? 255 : static_cast<std::uint8_t>(std::lround(v));
    }
    model.red[i] = channel[0];
    model.green[i] = channel[1];
    model.blue[i] = channel[2];
  }

  // Positions only: a non-finite normal is a missing one, for check_normals() to handle.
  void check_finite(const PointModel& m, std::size_t i) {
    const bool finite = std::isfinite(m.x[i]) && std::isfinite(m.y[i]) && std::isfinite(m.z[i]);
    if (!finite) fail("non-finite coordinate in vertex " + std::to_string(i));
    const std::string range = coordinate_range_problem(m.x[i], m.y[i], m.z[i], "vertex", i);
    if (!range.empty()) fail(range);
  }

  void read_faces(std::uint64_t count, PointModel& model) {
    const std::uint64_t vertex_count = model.size();
    // Reserve for triangles, but never more than the remaining text could hold.
    const std::uint64_t likely = std::min<std::uint64_t>(count, scanner_.remaining() / 8);
    model.triangles.reserve(static_cast<std::size_t>(likely) * 3);
    std::vector<std::uint32_t> polygon;
    std::string_view line;
    for (std::uint64_t f = 0; f < count; ++f) {
      if (!next_content_line(line)) {
        fail_at(scanner_.next_line_number(),
                "file truncated: expected " + std::to_string(count) + " faces, read " + std::to_string(f));
      }
      TokenCursor tokens(line);
      std::string_view token;
      tokens.next(token);
      std::uint64_t corners = 0;
      if (!parse_uint64(token, corners)) {
        fail("bad corner count " + quoted(token) + " for face " + std::to_string(f));
      }
      polygon.clear();
      for (std::uint64_t j = 0; j < corners; ++j) {
        if (!tokens.next(token)) {
          fail("face " + std::to_string(f) + " lists " + std::to_string(corners) + " corners but the line has only " +
               std::to_string(j) + " indices");
        }
        std::int64_t index = 0;
        if (!parse_int64(token, index)) {
          fail(quoted(token) + " is not a vertex index (face " + std::to_string(f) + ")");
        }
        if (index < 0 || static_cast<std::uint64_t>(index) >= vertex_count) {
          fail("face " + std::to_string(f) + " refers to vertex " + std::to_string(index) + ", but there are only " +
               std::to_string(vertex_count) + " vertices");
        }
        polygon.push_back(static_cast<std::uint32_t>(index));
      }
      // A face colour may follow the indices; it is ignored. Faces with fewer than three
      // corners have no area and are dropped; larger polygons are fanned.
      for (std::size_t j = 1; j + 1 < polygon.size(); ++j) {
        model.triangles.insert(model.triangles.end(), {polygon[0], polygon[j], polygon[j + 1]});
      }
    }
  }

  [[noreturn]] void fail(const std::string& problem) const { fail_at(scanner_.line_number(), problem); }
  [[noreturn]] void fail_at(std::size_t line, const std::string& problem) const {
    throw ModelFileError(name_, line_where(line), problem);
  }

  TextScanner scanner_;
  const std::string& name_;
};

}  // namespace

PointModel read_off_from_buffer(std::string_view text, const std::string& name_for_errors) {
  return OffParser(text, name_for_errors).parse();
}

PointModel read_off(const std::string& path) { return read_off_from_buffer(read_file_bytes(path), path); }

}  // namespace sculpt::deform
