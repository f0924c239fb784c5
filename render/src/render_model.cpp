#include "sculpt/render/render_model.hpp"

#include <algorithm>
#include <array>
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

// Each point's kLocalNeighbour nearest distinct neighbours (itself where it has fewer).
std::vector<std::uint32_t> nearest_distinct(const deform::PointModel& model, const deform::PointIndex& index) {
  std::vector<std::uint32_t> chosen(kLocalNeighbour * model.size());
  std::vector<std::uint32_t> neighbours;
  std::vector<double> squared;
  for (std::size_t i = 0; i < model.size(); ++i) {
    // A few more than needed, so coincident copies of the point do not count as neighbours.
    index.k_nearest(model.position(i), kLocalNeighbour + 5, neighbours, squared);
    std::size_t distinct = 0;
    for (std::size_t k = 0; k < neighbours.size() && distinct < kLocalNeighbour; ++k) {
      if (squared[k] > 0.0) chosen[kLocalNeighbour * i + distinct++] = neighbours[k];
    }
    for (; distinct < kLocalNeighbour; ++distinct)
      chosen[kLocalNeighbour * i + distinct] = static_cast<std::uint32_t>(i);
  }
  return chosen;
}

// A point's local spacing is the farthest of its chosen neighbours where they are now (at the
// build, its third nearest distinct neighbour); its splat the class nearest that spacing, in
// quarter octaves of the typical spacing (a point with no distinct neighbour: the typical).
// The class is found by counting the boundaries between classes that the squared spacing
// passes, with no logarithm or root per point: a live view sizes every point each frame
// (437,645 points: follow() about 6 ms, the classes 4 of it, where a log2 per point took 9).
std::vector<SplatClass> splat_classes_of(const std::vector<float>& xyz, const std::vector<std::uint32_t>& chosen,
                                         double typical) {
  constexpr int kClasses = kLargestClass - kSmallestClass + 1;
  std::vector<SplatClass> classes(kClasses);
  // boundary[c]: the squared spacing halfway (in quarter octaves) between class c and c + 1.
  std::array<double, kClasses - 1> boundary{};
  for (int c = kSmallestClass; c <= kLargestClass; ++c) {
    classes[c - kSmallestClass].diameter =
        kSplatsPerSpacing * typical * std::exp2(static_cast<double>(c) / kClassesPerOctave);
    if (c < kLargestClass) {
      boundary[c - kSmallestClass] = typical * typical * std::exp2((c + 0.5) * 2.0 / kClassesPerOctave);
    }
  }
  const std::size_t n = xyz.size() / 3;
  for (std::size_t i = 0; i < n; ++i) {
    double farthest = 0.0;
    for (std::size_t k = 0; k < kLocalNeighbour; ++k) {
      const std::size_t j = chosen[kLocalNeighbour * i + k];
      const double dx = double{xyz[3 * j]} - xyz[3 * i], dy = double{xyz[3 * j + 1]} - xyz[3 * i + 1],
                   dz = double{xyz[3 * j + 2]} - xyz[3 * i + 2];
      farthest = std::max(farthest, dx * dx + dy * dy + dz * dz);
    }
    int c = -kSmallestClass;  // class 0, the typical spacing
    if (farthest > 0.0) {
      c = 0;
      for (const double b : boundary) c += farthest > b;
    }
    classes[c].points.push_back(static_cast<std::uint32_t>(i));
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
  if (triangles_.empty()) {
    const deform::PointIndex index(model);
    typical_spacing_ = deform::typical_spacing(model, index).value;
    splat_neighbours_ = nearest_distinct(model, index);
    splat_classes_ = splat_classes_of(positions_, splat_neighbours_, typical_spacing_);
  }
}

void RenderModel::follow(const deform::PointModel& model) {
  if (model.size() != size()) {
    throw std::invalid_argument("a model of " + std::to_string(model.size()) + " points cannot move one of " +
                                std::to_string(size()));
  }
  take_positions(model);
  take_normals(model);
  if (!splat_neighbours_.empty()) splat_classes_ = splat_classes_of(positions_, splat_neighbours_, typical_spacing_);
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
