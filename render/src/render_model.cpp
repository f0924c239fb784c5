#include "sculpt/render/render_model.hpp"

#include <stdexcept>
#include <string>

#include "sculpt/deform/model_scale.hpp"
#include "sculpt/deform/normals.hpp"
#include "sculpt/deform/point_index.hpp"

namespace sculpt::render {

RenderModel::RenderModel(const deform::PointModel& model) {
  if (model.empty()) throw std::invalid_argument("the model has no points to draw");
  triangles_ = model.triangles;
  const std::size_t n = model.size();
  positions_.resize(3 * n);
  for (std::size_t i = 0; i < n; ++i) {
    positions_[3 * i] = model.x[i];
    positions_[3 * i + 1] = model.y[i];
    positions_[3 * i + 2] = model.z[i];
  }

  // Normals are only for shading, so the estimate works on a copy rather than asking the
  // caller to give up a const model.
  const deform::PointModel* with_normals = &model;
  deform::PointModel copy;
  if (!model.has_normals()) {
    copy = model;
    deform::ensure_normals(copy);
    with_normals = &copy;
  }
  normals_.resize(3 * n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 u = normalized(with_normals->normal(i));
    normals_[3 * i] = static_cast<float>(u.x);
    normals_[3 * i + 1] = static_cast<float>(u.y);
    normals_[3 * i + 2] = static_cast<float>(u.z);
  }

  colors_.resize(3 * n);
  for (std::size_t i = 0; i < n; ++i) {
    const bool own = model.has_colors();
    colors_[3 * i] = own ? model.red[i] / 255.0f : static_cast<float>(kClayColor.r);
    colors_[3 * i + 1] = own ? model.green[i] / 255.0f : static_cast<float>(kClayColor.g);
    colors_[3 * i + 2] = own ? model.blue[i] / 255.0f : static_cast<float>(kClayColor.b);
  }

  if (triangles_.empty()) {
    // Splats as wide as the typical gap between neighbours, so the points close into a surface.
    splat_diameter_ = kSplatsPerSpacing * deform::typical_spacing(model, deform::PointIndex(model)).value;
  }
}

void RenderModel::set_colors(const std::vector<Rgb>& colors) {
  if (colors.size() != size()) {
    throw std::invalid_argument(std::to_string(colors.size()) + " colours for a model of " + std::to_string(size()) +
                                " points");
  }
  for (std::size_t i = 0; i < colors.size(); ++i) {
    colors_[3 * i] = static_cast<float>(colors[i].r);
    colors_[3 * i + 1] = static_cast<float>(colors[i].g);
    colors_[3 * i + 2] = static_cast<float>(colors[i].b);
  }
}

}  // namespace sculpt::render
