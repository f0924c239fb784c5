#pragma once
// The "x y z [nx ny nz]" text the ascii writers (PLY ascii, OFF, XYZ) all start a vertex with.

#include <cstddef>
#include <string>

#include "number_text.hpp"
#include "sculpt/deform/point_model.hpp"

namespace sculpt::deform {

/// Appends point i's position, and its normal when the model has normals, as shortest-digit
/// floats separated by single spaces; no line end.
inline void append_vertex_text(std::string& out, const PointModel& m, std::size_t i) {
  append_float(out, m.x[i]);
  out += ' ';
  append_float(out, m.y[i]);
  out += ' ';
  append_float(out, m.z[i]);
  if (m.has_normals()) {
    for (float v : {m.nx[i], m.ny[i], m.nz[i]}) {
      out += ' ';
      append_float(out, v);
    }
  }
}

/// Appends "3 a b c\n" for every triangle: the face line of PLY ascii and OFF alike.
inline void append_triangle_lines(std::string& out, const PointModel& m) {
  for (std::size_t t = 0; t < m.triangles.size(); t += 3) {
    out += '3';
    for (std::size_t k = 0; k < 3; ++k) {
      out += ' ';
      append_uint(out, m.triangles[t + k]);
    }
    out += '\n';
  }
}

}  // namespace sculpt::deform
