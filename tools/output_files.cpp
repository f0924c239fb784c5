#include "output_files.hpp"

#include "output_paths.hpp"
#include "sculpt/render/png_file.hpp"

namespace sculpt::tools {

void write_model_output(const std::string& path, const deform::PointModel& model, deform::PlyEncoding encoding) {
  create_parent_folders(path);
  deform::write_model(path, model, encoding);
}

void write_picture_output(const std::string& path, const render::Image& picture) {
  create_parent_folders(path);
  render::write_png(path, picture);
}

}  // namespace sculpt::tools
