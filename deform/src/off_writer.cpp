// OFF writing: "[C][N]OFF", the counts, one vertex per line (position, normal, RGBA colour) and
// one "3 a b c" line per triangle, as Geomview, MeshLab and our own reader read it.

#include <string>

#include "number_text.hpp"
#include "sculpt/deform/atomic_file.hpp"
#include "sculpt/deform/model_io.hpp"
#include "vertex_text.hpp"
#include "writable_model.hpp"

namespace sculpt::deform {

std::string write_off_to_buffer(const PointModel& model) {
  check_writable(model, "write_off");
  std::string out;
  if (model.has_colors()) out += 'C';
  if (model.has_normals()) out += 'N';
  out += "OFF\n";
  append_uint(out, model.size());
  out += ' ';
  append_uint(out, model.triangles.size() / 3);
  out += " 0\n";  // the edge count, which no reader uses
  for (std::size_t i = 0; i < model.size(); ++i) {
    append_vertex_text(out, model, i);
    if (model.has_colors()) {
      // Integers, so readers take them as 0..255 rather than 0..1; alpha is 255 (opaque) when
      // the model has none, since readers of COFF expect four channels.
      for (std::uint8_t v :
           {model.red[i], model.green[i], model.blue[i], model.has_alpha() ? model.alpha[i] : std::uint8_t{255}}) {
        out += ' ';
        append_uint(out, v);
      }
    }
    out += '\n';
  }
  append_triangle_lines(out, model);
  return out;
}

void write_off(const std::string& path, const PointModel& model) {
  write_file_atomically(path, write_off_to_buffer(model));
}

}  // namespace sculpt::deform
