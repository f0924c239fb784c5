#pragma once
// The commands' model and picture outputs written where check_outputs (output_paths.hpp) found
// they could be: each writer makes the folders on the way that are still missing, so no command
// can check an output and then fail to write it for want of a folder. (JSON summaries:
// write_json, json_report.hpp, does the same.)

#include <string>

#include "sculpt/deform/model_io.hpp"
#include "sculpt/render/image.hpp"

namespace sculpt::tools {

/// deform::write_model after create_parent_folders.
void write_model_output(const std::string& path, const deform::PointModel& model,
                        deform::PlyEncoding encoding = deform::PlyEncoding::kBinaryLittleEndian);

/// render::write_png after create_parent_folders.
void write_picture_output(const std::string& path, const render::Image& picture);

}  // namespace sculpt::tools
