// XYZ writing: the simplest exchange format, "x y z [nx ny nz]" per line.

#include <string>

#include "number_text.hpp"
#include "sculpt/deform/atomic_file.hpp"
#include "sculpt/deform/model_io.hpp"

namespace sculpt::deform {

std::string write_xyz_to_buffer(const PointModel& model) {
  model.validate();
  std::string out;
  out.reserve(model.size() * (model.has_normals() ? 72 : 36));
  for (std::size_t i = 0; i < model.size(); ++i) {
    append_float(out, model.x[i]);
    out += ' ';
    append_float(out, model.y[i]);
    out += ' ';
    append_float(out, model.z[i]);
    if (model.has_normals()) {
      for (float v : {model.nx[i], model.ny[i], model.nz[i]}) {
        out += ' ';
        append_float(out, v);
      }
    }
    out += '\n';
  }
  return out;
}

void write_xyz(const std::string& path, const PointModel& model) {
  write_file_atomically(path, write_xyz_to_buffer(model));
}

}  // namespace sculpt::deform
