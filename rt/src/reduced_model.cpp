#include "sculpt/rt/reduced_model.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>

#include "sculpt/base/number_text.hpp"

namespace sculpt::rt {
namespace {

// 21 bits per axis pack a voxel's coordinates into one 64-bit key; the finest voxel the search
// tries keeps every axis below that.
constexpr int kAxisBits = 21;
constexpr double kFinestCells = static_cast<double>(1u << 20);
constexpr int kMaxBisections = 60;

struct Box {
  double min[3];
  double extent;  // largest edge
};

Box bounds(const deform::PointModel& m) {
  Box b{{m.x[0], m.y[0], m.z[0]}, 0.0};
  double max[3] = {b.min[0], b.min[1], b.min[2]};
  for (std::size_t i = 0; i < m.size(); ++i) {
    const double p[3] = {m.x[i], m.y[i], m.z[i]};
    for (int a = 0; a < 3; ++a) {
      b.min[a] = std::min(b.min[a], p[a]);
      max[a] = std::max(max[a], p[a]);
    }
  }
  for (int a = 0; a < 3; ++a) b.extent = std::max(b.extent, max[a] - b.min[a]);
  return b;
}

/// One voxel-grid pass at voxel size h: per voxel, the point nearest its centre (ties to the
/// smaller index). `order` is scratch; the kept indices come back ascending.
void voxel_subsample(const deform::PointModel& m, const Box& box, double h, std::vector<std::uint64_t>& keys,
                     std::vector<double>& d2, std::vector<std::uint32_t>& order, std::vector<std::uint32_t>& kept) {
  const std::size_t n = m.size();
  keys.resize(n);
  d2.resize(n);
  order.resize(n);
  constexpr std::uint64_t kMask = (std::uint64_t{1} << kAxisBits) - 1;
  for (std::size_t i = 0; i < n; ++i) {
    const double p[3] = {m.x[i], m.y[i], m.z[i]};
    std::uint64_t key = 0;
    double d = 0.0;
    for (int a = 0; a < 3; ++a) {
      const double cell = std::floor((p[a] - box.min[a]) / h);
      const double centre = box.min[a] + (cell + 0.5) * h;
      d += (p[a] - centre) * (p[a] - centre);
      key = (key << kAxisBits) | (static_cast<std::uint64_t>(cell) & kMask);
    }
    keys[i] = key;
    d2[i] = d;
  }
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    if (keys[a] != keys[b]) return keys[a] < keys[b];
    if (d2[a] != d2[b]) return d2[a] < d2[b];
    return a < b;
  });
  kept.clear();
  for (std::size_t k = 0; k < n; ++k) {
    if (k == 0 || keys[order[k]] != keys[order[k - 1]]) kept.push_back(order[k]);
  }
  std::sort(kept.begin(), kept.end());
}

}  // namespace

std::vector<std::uint32_t> reduced_indices(const deform::PointModel& full, double ratio) {
  if (!(ratio > 0.0 && ratio <= 1.0)) {
    throw std::invalid_argument("reduced model: ratio " + base::number_text(ratio) + " must be in (0, 1]");
  }
  const std::size_t n = full.size();
  std::vector<std::uint32_t> kept;
  if (ratio == 1.0 || n <= 1) {
    kept.resize(n);
    std::iota(kept.begin(), kept.end(), 0u);
    return kept;
  }
  const Box box = bounds(full);
  const double target = std::max(1.0, std::round(ratio * static_cast<double>(n)));
  if (!(box.extent > 0.0)) return {0};  // every point coincides: one voxel

  std::vector<std::uint64_t> keys;
  std::vector<double> d2;
  std::vector<std::uint32_t> order, trial, best;
  double best_error = std::numeric_limits<double>::infinity();
  // The count falls (not strictly) as the voxel grows: bisect the size on a log scale between
  // a grid fine enough to keep nearly every point and one voxel holding the whole model.
  double lo = std::log(box.extent / kFinestCells);
  double hi = std::log(box.extent * 1.01);
  for (int step = 0; step < kMaxBisections; ++step) {
    const double mid = 0.5 * (lo + hi);
    voxel_subsample(full, box, std::exp(mid), keys, d2, order, trial);
    const double count = static_cast<double>(trial.size());
    const double error = std::abs(count - target);
    if (error < best_error) {
      best_error = error;
      best.swap(trial);
    }
    if (best_error <= kReducedCountTolerance * target) break;
    if (count > target) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
  return best;
}

deform::PointModel reduced_model(const deform::PointModel& full, double ratio) {
  const std::vector<std::uint32_t> kept = reduced_indices(full, ratio);
  if (kept.size() == full.size()) return full;  // every point kept, in order: unchanged
  deform::PointModel out;
  out.resize(kept.size(), full.has_normals(), full.has_colors(), full.has_alpha());
  for (std::size_t k = 0; k < kept.size(); ++k) {
    const std::uint32_t i = kept[k];
    out.x[k] = full.x[i];
    out.y[k] = full.y[i];
    out.z[k] = full.z[i];
    if (full.has_normals()) {
      out.nx[k] = full.nx[i];
      out.ny[k] = full.ny[i];
      out.nz[k] = full.nz[i];
    }
    if (full.has_colors()) {
      out.red[k] = full.red[i];
      out.green[k] = full.green[i];
      out.blue[k] = full.blue[i];
    }
    if (full.has_alpha()) out.alpha[k] = full.alpha[i];
  }
  return out;
}

ModelDifference compare_models(const deform::PointModel& reference, const deform::PointModel& other) {
  if (reference.size() != other.size()) {
    throw std::invalid_argument("compare models: " + std::to_string(reference.size()) + " and " +
                                std::to_string(other.size()) + " points");
  }
  ModelDifference d;
  if (reference.empty()) return d;
  const double diagonal = reference.bounding_box_diagonal();
  const double scale = diagonal > 0.0 ? 1.0 / diagonal : 1.0;
  double sum = 0.0;
  for (std::size_t i = 0; i < reference.size(); ++i) {
    const double distance = norm(reference.position(i) - other.position(i));
    sum += distance;
    d.max = std::max(d.max, distance);
  }
  d.mean = sum / static_cast<double>(reference.size()) * scale;
  d.max *= scale;
  return d;
}

}  // namespace sculpt::rt
