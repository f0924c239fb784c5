#include "sculpt/deform/normals.hpp"

#include <Eigen/Core>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <numeric>
#include <queue>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "sculpt/deform/point_index.hpp"

namespace sculpt::deform {
namespace {

constexpr std::size_t kMinNeighbours = 3;  // fewer points do not span a plane

std::size_t neighbourhood_size(const NormalEstimation& options) { return std::max(options.neighbours, kMinNeighbours); }

/// The k-NN lists of every point, flattened: row i holds point i's neighbours (itself
/// included), `width` slots per row, unused slots set to the point itself.
struct NeighbourTable {
  std::size_t width = 0;
  std::vector<std::uint32_t> ids;

  const std::uint32_t* row(std::size_t i) const { return ids.data() + i * width; }
};

// Unit normal of the best-fit plane through `count` points (smallest-eigenvalue eigenvector
// of their covariance). Coordinates are taken relative to `origin` so float models far from the
// origin keep their precision.
Vec3 pca_normal(const PointModel& model, const std::uint32_t* ids, std::size_t count, const Vec3& origin) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (std::size_t j = 0; j < count; ++j) {
    const Vec3 d = model.position(ids[j]) - origin;
    mean += Eigen::Vector3d(d.x, d.y, d.z);
  }
  mean /= static_cast<double>(count);
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (std::size_t j = 0; j < count; ++j) {
    const Vec3 d = model.position(ids[j]) - origin;
    const Eigen::Vector3d centred = Eigen::Vector3d(d.x, d.y, d.z) - mean;
    covariance.selfadjointView<Eigen::Lower>().rankUpdate(centred);
  }
  // The iterative solver, not computeDirect(): the closed form loses the small eigenvector's
  // accuracy on thin neighbourhoods, which is exactly the case that matters here.
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance.selfadjointView<Eigen::Lower>(),
                                                              Eigen::ComputeEigenvectors);
  const Eigen::Vector3d n = solver.eigenvectors().col(0);  // eigenvalues come ascending
  return normalized(Vec3{n.x(), n.y(), n.z()});
}

NeighbourTable k_nearest_table(const PointModel& model, const PointIndex& index, std::size_t k) {
  NeighbourTable table;
  table.width = std::min(k, model.size());
  table.ids.resize(model.size() * table.width);
  std::vector<std::uint32_t> ids;
  std::vector<double> squared;
  for (std::size_t i = 0; i < model.size(); ++i) {
    index.k_nearest(model.position(i), table.width, ids, squared);
    std::uint32_t* row = table.ids.data() + i * table.width;
    std::fill(row, row + table.width, static_cast<std::uint32_t>(i));
    std::copy(ids.begin(), ids.end(), row);
  }
  return table;
}

void write_normals(PointModel& model, const std::vector<Vec3>& normals) {
  model.resize(model.size(), /*with_normals=*/true, /*with_colors=*/false);
  for (std::size_t i = 0; i < normals.size(); ++i) model.set_normal(i, normals[i]);
}

std::vector<Vec3> read_normals(const PointModel& model) {
  std::vector<Vec3> normals(model.size());
  for (std::size_t i = 0; i < model.size(); ++i) normals[i] = model.normal(i);
  return normals;
}

void orient_toward(const PointModel& model, const Vec3& reference, std::vector<Vec3>& normals) {
  for (std::size_t i = 0; i < normals.size(); ++i) {
    if (dot(normals[i], reference - model.position(i)) < 0.0) normals[i] = -normals[i];
  }
}

// Hoppe et al. 1992: carry the sign from point to point along a minimum spanning tree whose
// edges are cheap where neighbouring normals are nearly parallel, so the sign is never passed
// across a fold or a sharp edge while a smoother path exists.
void orient_along_mst(const PointModel& model, const NeighbourTable& table, std::vector<Vec3>& normals) {
  const std::size_t n = model.size();
  // Symmetric adjacency in compressed rows: a k-NN relation is one-sided, and the tree must be
  // able to step either way along it.
  std::vector<std::size_t> start(n + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t s = 0; s < table.width; ++s) {
      const std::uint32_t j = table.row(i)[s];
      if (j == i) continue;
      ++start[i + 1];
      ++start[j + 1];
    }
  }
  std::partial_sum(start.begin(), start.end(), start.begin());
  std::vector<std::uint32_t> adjacent(start[n]);
  std::vector<std::size_t> fill(start.begin(), start.end() - 1);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t s = 0; s < table.width; ++s) {
      const std::uint32_t j = table.row(i)[s];
      if (j == i) continue;
      adjacent[fill[i]++] = j;
      adjacent[fill[j]++] = static_cast<std::uint32_t>(i);
    }
  }
  // Mutual neighbours were listed twice; dropping the repeats halves the heap traffic below.
  std::size_t kept = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const auto row_begin = adjacent.begin() + static_cast<std::ptrdiff_t>(start[i]);
    const auto row_end = adjacent.begin() + static_cast<std::ptrdiff_t>(start[i + 1]);
    std::sort(row_begin, row_end);
    const auto unique_end = std::unique(row_begin, row_end);
    start[i] = kept;
    kept = static_cast<std::size_t>(
        std::copy(row_begin, unique_end, adjacent.begin() + static_cast<std::ptrdiff_t>(kept)) - adjacent.begin());
  }
  start[n] = kept;

  // Seeds in order of decreasing x: each new component starts at its own largest-x point.
  std::vector<std::uint32_t> by_x(n);
  std::iota(by_x.begin(), by_x.end(), 0u);
  std::stable_sort(by_x.begin(), by_x.end(), [&](std::uint32_t a, std::uint32_t b) { return model.x[a] > model.x[b]; });

  // Prim's algorithm with lazy deletion: (weight, node, parent), smallest weight first.
  using Edge = std::tuple<double, std::uint32_t, std::uint32_t>;
  std::priority_queue<Edge, std::vector<Edge>, std::greater<Edge>> frontier;
  std::vector<std::uint8_t> reached(n, 0);
  auto push_edges = [&](std::uint32_t from) {
    for (std::size_t e = start[from]; e < start[from + 1]; ++e) {
      const std::uint32_t to = adjacent[e];
      if (reached[to]) continue;
      frontier.emplace(1.0 - std::abs(dot(normals[from], normals[to])), to, from);
    }
  };
  for (const std::uint32_t seed : by_x) {
    if (reached[seed]) continue;
    if (normals[seed].x < 0.0) normals[seed] = -normals[seed];
    reached[seed] = 1;
    push_edges(seed);
    while (!frontier.empty()) {
      const auto [weight, node, parent] = frontier.top();
      frontier.pop();
      if (reached[node]) continue;
      if (dot(normals[parent], normals[node]) < 0.0) normals[node] = -normals[node];
      reached[node] = 1;
      push_edges(node);
    }
  }
}

}  // namespace

void estimate_normals(PointModel& model, const NormalEstimation& options) {
  const std::size_t n = model.size();
  if (n == 0) return;
  const PointIndex index(model);
  const NeighbourTable table = k_nearest_table(model, index, neighbourhood_size(options));
  std::vector<Vec3> normals(n);
  for (std::size_t i = 0; i < n; ++i) {
    normals[i] = pca_normal(model, table.row(i), table.width, model.position(i));
  }
  if (options.reference) {
    orient_toward(model, *options.reference, normals);
  } else {
    orient_along_mst(model, table, normals);
  }
  write_normals(model, normals);
}

void orient_normals(PointModel& model, const NormalEstimation& options) {
  if (model.empty()) return;
  if (!model.has_normals()) {
    throw std::invalid_argument("orient_normals: the model has no normals to orient");
  }
  std::vector<Vec3> normals = read_normals(model);
  if (options.reference) {
    orient_toward(model, *options.reference, normals);
  } else {
    const PointIndex index(model);
    orient_along_mst(model, k_nearest_table(model, index, neighbourhood_size(options)), normals);
  }
  write_normals(model, normals);
}

FaceOrientation compute_normals_from_faces(PointModel& model) {
  const std::size_t n = model.size();
  const std::vector<std::uint32_t>& tri = model.triangles;
  if (tri.size() % 3 != 0) {
    throw std::invalid_argument("compute_normals_from_faces: triangle index count " + std::to_string(tri.size()) +
                                " is not a multiple of 3");
  }
  for (std::size_t t = 0; t < tri.size(); t += 3) {
    if (tri[t] >= n || tri[t + 1] >= n || tri[t + 2] >= n) {
      throw std::invalid_argument("compute_normals_from_faces: triangle " + std::to_string(t / 3) +
                                  " refers to a point out of range");
    }
  }
  const FaceOrientation wound = orient_faces(model);
  std::vector<Vec3> normals(n);
  for (std::size_t t = 0; t < tri.size(); t += 3) {
    const std::uint32_t a = tri[t], b = tri[t + 1], c = tri[t + 2];
    const Vec3 pa = model.position(a);
    // Twice the face's area along its normal: summing these weighs faces by area.
    const Vec3 face = cross(model.position(b) - pa, model.position(c) - pa);
    normals[a] += face;
    normals[b] += face;
    normals[c] += face;
  }

  std::vector<std::uint32_t> faceless;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 unit = normalized(normals[i]);
    if (squared_norm(unit) == 0.0) faceless.push_back(static_cast<std::uint32_t>(i));
    normals[i] = unit;
  }
  if (faceless.size() == n) {
    estimate_normals(model);
    return wound;
  }
  write_normals(model, normals);
  // A faceless point (a stray vertex, an unmeshed patch) takes its plane from all nearby
  // points and its side from the closest point whose side the mesh has already settled.
  reestimate_normals(model, faceless);
  return wound;
}

void reestimate_normals(PointModel& model, const std::vector<std::uint32_t>& points) {
  if (points.empty()) return;
  if (!model.has_normals()) {
    throw std::invalid_argument("reestimate_normals: the model has no normals to keep");
  }
  const std::size_t n = model.size();
  std::vector<std::uint8_t> listed(n, 0);
  std::size_t unique = 0;
  for (const std::uint32_t i : points) {
    if (i >= n) {
      throw std::invalid_argument("reestimate_normals: point " + std::to_string(i) + " of " + std::to_string(n));
    }
    unique += listed[i] == 0 ? 1 : 0;
    listed[i] = 1;
  }
  if (unique == n) {
    ensure_normals(model, /*force=*/true);
    return;
  }
  PointModel settled;  // positions of the points whose normals stay
  std::vector<std::uint32_t> settled_id;
  for (std::size_t i = 0; i < n; ++i) {
    if (listed[i]) continue;
    settled.push_back(model.position(i));
    settled_id.push_back(static_cast<std::uint32_t>(i));
  }
  const PointIndex all(model);
  const PointIndex settled_index(settled);
  const std::size_t k = std::min(neighbourhood_size(NormalEstimation{}), n);
  std::vector<std::uint32_t> ids;
  std::vector<double> squared;
  // Only settled normals guide, and they are never written here, so the order does not matter.
  for (std::size_t i = 0; i < n; ++i) {
    if (!listed[i]) continue;
    const Vec3 p = model.position(i);
    all.k_nearest(p, k, ids, squared);
    Vec3 normal = pca_normal(model, ids.data(), ids.size(), p);
    const Vec3 guide = model.normal(settled_id[settled_index.nearest(settled, p).index]);
    if (dot(normal, guide) < 0.0) normal = -normal;
    model.set_normal(i, normal);
  }
}

FaceOrientation ensure_normals(PointModel& model, bool force) {
  if (model.has_normals() && !force) return {};
  if (!model.triangles.empty()) return compute_normals_from_faces(model);
  estimate_normals(model);
  return {};
}

}  // namespace sculpt::deform
