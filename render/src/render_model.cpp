#include "sculpt/render/render_model.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "sculpt/deform/model_scale.hpp"
#include "sculpt/deform/normals.hpp"
#include "sculpt/deform/point_index.hpp"

namespace sculpt::render {
namespace {

// Splat sizes are quantised to quarter octaves (19% apart) of the typical spacing, and kept
// between half and four times it, so a stray point far from the rest is not a huge disc.
constexpr int kClassesPerOctave = 4;
constexpr int kSmallestClass = -kClassesPerOctave;
constexpr int kLargestClass = 2 * kClassesPerOctave;
constexpr std::size_t kLocalNeighbour = 3;

std::vector<SplatClass> make_splat_classes(const deform::PointModel& model) {
  const deform::PointIndex index(model);
  const double typical = deform::typical_spacing(model, index).value;
  std::vector<SplatClass> classes(kLargestClass - kSmallestClass + 1);
  for (int c = kSmallestClass; c <= kLargestClass; ++c) {
    classes[c - kSmallestClass].diameter =
        kSplatsPerSpacing * typical * std::exp2(static_cast<double>(c) / kClassesPerOctave);
  }
  std::vector<std::uint32_t> neighbours;
  std::vector<double> squared;
  for (std::size_t i = 0; i < model.size(); ++i) {
    // A few more than needed, so coincident copies of the point do not count as neighbours.
    index.k_nearest(model.position(i), kLocalNeighbour + 5, neighbours, squared);
    double local = 0.0;
    std::size_t distinct = 0;
    for (const double d2 : squared) {
      if (d2 > 0.0 && ++distinct <= kLocalNeighbour) local = std::sqrt(d2);
    }
    const int c = local > 0.0 ? static_cast<int>(std::lround(kClassesPerOctave * std::log2(local / typical))) : 0;
    classes[std::clamp(c, kSmallestClass, kLargestClass) - kSmallestClass].points.push_back(
        static_cast<std::uint32_t>(i));
  }
  std::erase_if(classes, [](const SplatClass& s) { return s.points.empty(); });
  return classes;
}

}  // namespace

void RenderModel::take_positions(const deform::PointModel& model) {
  const std::size_t n = model.size();
  positions_.resize(3 * n);
  for (std::size_t i = 0; i < n; ++i) {
    positions_[3 * i] = model.x[i];
    positions_[3 * i + 1] = model.y[i];
    positions_[3 * i + 2] = model.z[i];
  }
}

void RenderModel::take_normals(const deform::PointModel& model) {
  // Normals are only for shading, so the estimate works on a copy rather than asking the
  // caller to give up a const model.
  const deform::PointModel* with_normals = &model;
  deform::PointModel copy;
  if (!model.has_normals()) {
    copy = model;
    deform::ensure_normals(copy);
    with_normals = &copy;
  }
  const std::size_t n = model.size();
  normals_.resize(3 * n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 u = normalized(with_normals->normal(i));
    normals_[3 * i] = static_cast<float>(u.x);
    normals_[3 * i + 1] = static_cast<float>(u.y);
    normals_[3 * i + 2] = static_cast<float>(u.z);
  }
}

RenderModel::RenderModel(const deform::PointModel& model) {
  if (model.empty()) throw std::invalid_argument("the model has no points to draw");
  triangles_ = model.triangles;
  take_positions(model);
  take_normals(model);

  const std::size_t n = model.size();
  colors_.resize(3 * n);
  for (std::size_t i = 0; i < n; ++i) {
    const bool own = model.has_colors();
    colors_[3 * i] = own ? model.red[i] / 255.0f : static_cast<float>(kClayColor.r);
    colors_[3 * i + 1] = own ? model.green[i] / 255.0f : static_cast<float>(kClayColor.g);
    colors_[3 * i + 2] = own ? model.blue[i] / 255.0f : static_cast<float>(kClayColor.b);
  }

  // Splats as wide as the gaps around each point, so the points close into a surface.
  if (triangles_.empty()) splat_classes_ = make_splat_classes(model);
}

void RenderModel::follow(const deform::PointModel& model) {
  if (model.size() != size()) {
    throw std::invalid_argument("a model of " + std::to_string(model.size()) + " points cannot move one of " +
                                std::to_string(size()));
  }
  take_positions(model);
  take_normals(model);
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
