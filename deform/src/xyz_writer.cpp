// XYZ writing: the simplest exchange format, "x y z [nx ny nz]" per line.

#include <string>

#include "sculpt/deform/atomic_file.hpp"
#include "sculpt/deform/model_io.hpp"
#include "vertex_text.hpp"
#include "writable_model.hpp"

namespace sculpt::deform {

std::string write_xyz_to_buffer(const PointModel& model) {
  check_writable(model, "write_xyz");
  std::string out;
  out.reserve(model.size() * (model.has_normals() ? 72 : 36));
  for (std::size_t i = 0; i < model.size(); ++i) {
    append_vertex_text(out, model, i);
    out += '\n';
  }
  return out;
}

void write_xyz(const std::string& path, const PointModel& model) {
  write_file_atomically(path, write_xyz_to_buffer(model));
}

}  // namespace sculpt::deform
