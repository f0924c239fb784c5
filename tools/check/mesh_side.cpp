#include "mesh_side.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

namespace sculpt::tools::check {

using deform::Vec3;

namespace {

std::uint64_t edge_key(std::uint32_t u, std::uint32_t v) {
  const std::uint64_t lo = std::min(u, v), hi = std::max(u, v);
  return lo << 32 | hi;
}

// The interior angle of the triangle at corner p (between the edges to q and r).
double corner_angle(const Vec3& p, const Vec3& q, const Vec3& r) {
  const Vec3 u = q - p, v = r - p;
  return std::atan2(norm(cross(u, v)), dot(u, v));
}

// Van Oosterom and Strackee's tan(omega / 2), with the corners' lengths given (a query computes
// them once per vertex, not once per corner).
double solid_angle_of(const Vec3& a, const Vec3& b, const Vec3& c, double la, double lb, double lc) {
  const double den = la * lb * lc + dot(a, b) * lc + dot(b, c) * la + dot(c, a) * lb;
  return 2.0 * std::atan2(dot(a, cross(b, c)), den);
}

}  // namespace

TriangleClosest closest_on_triangle(const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c) {
  using Feature = TriangleClosest::Feature;
  // q's projections on the two edges from each corner decide its Voronoi region: a corner when
  // both point away from the triangle, an edge when q is beyond it and between its ends.
  const Vec3 ab = b - a, ac = c - a;
  const Vec3 aq = q - a;
  const double d1 = dot(ab, aq), d2 = dot(ac, aq);
  if (d1 <= 0.0 && d2 <= 0.0) return {a, Feature::kVertex, 0};
  const Vec3 bq = q - b;
  const double d3 = dot(ab, bq), d4 = dot(ac, bq);
  if (d3 >= 0.0 && d4 <= d3) return {b, Feature::kVertex, 1};
  const Vec3 cq = q - c;
  const double d5 = dot(ab, cq), d6 = dot(ac, cq);
  if (d6 >= 0.0 && d5 <= d6) return {c, Feature::kVertex, 2};
  // Twice the signed areas of the sub-triangles opposite each corner, scaled by |ab x ac|: the
  // unnormalized barycentric coordinates of q's projection. A negative one puts q beyond an edge.
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return {a + ab * (d1 / (d1 - d3)), Feature::kEdge, 0};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return {a + ac * (d2 / (d2 - d6)), Feature::kEdge, 2};
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) {
    return {b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))), Feature::kEdge, 1};
  }
  const double sum = va + vb + vc;
  if (!(sum > 0.0)) {
    // Degenerate (collinear corners) and no region above claimed q: the nearest of its edges.
    TriangleClosest best{a, Feature::kVertex, 0};
    double best_d = squared_norm(q - a);
    const Vec3 corners[3] = {a, b, c};
    for (int e = 0; e < 3; ++e) {
      const Vec3 p = corners[e], d = corners[(e + 1) % 3] - p;
      const double len = squared_norm(d);
      const double t = len > 0.0 ? std::clamp(dot(q - p, d) / len, 0.0, 1.0) : 0.0;
      const Vec3 x = p + d * t;
      if (squared_norm(q - x) < best_d) best = {x, Feature::kEdge, e}, best_d = squared_norm(q - x);
    }
    return best;
  }
  return {a + ab * (vb / sum) + ac * (vc / sum), Feature::kFace, 0};
}

double solid_angle(const Vec3& a, const Vec3& b, const Vec3& c) {
  return solid_angle_of(a, b, c, norm(a), norm(b), norm(c));
}

MeshSideOracle::MeshSideOracle(std::vector<std::uint32_t> triangles, std::size_t point_count)
    : triangles_(std::move(triangles)), point_count_(point_count) {
  if (triangles_.empty() || triangles_.size() % 3 != 0) {
    throw std::invalid_argument("mesh oracle: " + std::to_string(triangles_.size()) +
                                " triangle indices (need a positive multiple of 3)");
  }
  for (std::uint32_t i : triangles_) {
    if (i >= point_count_) {
      throw std::invalid_argument("mesh oracle: index " + std::to_string(i) + " for " + std::to_string(point_count_) +
                                  " points");
    }
  }
  const std::size_t nt = triangle_count();
  edge_triangles_.reserve(3 * nt);
  for (std::size_t t = 0; t < nt; ++t) {
    for (int e = 0; e < 3; ++e) {
      edge_triangles_.push_back(
          {edge_key(triangles_[3 * t + e], triangles_[3 * t + (e + 1) % 3]), static_cast<std::uint32_t>(t)});
    }
  }
  std::sort(edge_triangles_.begin(), edge_triangles_.end());
  closed_ = true;
  for (std::size_t i = 0; i < edge_triangles_.size();) {
    std::size_t j = i;
    while (j < edge_triangles_.size() && edge_triangles_[j].first == edge_triangles_[i].first) ++j;
    if (j - i != 2) closed_ = false;
    i = j;
  }
  vertex_offsets_.assign(point_count_ + 1, 0);
  for (std::uint32_t i : triangles_) ++vertex_offsets_[i + 1];
  for (std::size_t v = 0; v < point_count_; ++v) vertex_offsets_[v + 1] += vertex_offsets_[v];
  vertex_triangles_.resize(triangles_.size());
  std::vector<std::uint32_t> fill(vertex_offsets_.begin(), vertex_offsets_.end() - 1);
  for (std::size_t k = 0; k < triangles_.size(); ++k) {
    vertex_triangles_[fill[triangles_[k]]++] = static_cast<std::uint32_t>(k / 3);
  }
}

Vec3 MeshSideOracle::face_normal(std::size_t t) const {
  const Vec3 a = relative_[triangles_[3 * t]], b = relative_[triangles_[3 * t + 1]],
             c = relative_[triangles_[3 * t + 2]];
  const Vec3 n = cross(b - a, c - a);
  const double len = norm(n);
  return len > 0.0 ? n * (1.0 / len) : Vec3{};
}

// Baerentzen and Aanaes: at a face its normal, at an edge the sum of its faces' normals, at a
// vertex the sum of its faces' normals weighted by their angles there. With these, the sign of
// (q - nearest) . pseudo-normal is the side of q for a consistently wound mesh.
Vec3 MeshSideOracle::pseudo_normal(std::size_t t, const TriangleClosest& c) const {
  using Feature = TriangleClosest::Feature;
  if (c.feature == Feature::kFace) return face_normal(t);
  Vec3 sum;
  if (c.feature == Feature::kEdge) {
    const std::uint64_t key = edge_key(triangles_[3 * t + c.index], triangles_[3 * t + (c.index + 1) % 3]);
    auto it = std::lower_bound(edge_triangles_.begin(), edge_triangles_.end(), std::make_pair(key, std::uint32_t{0}));
    for (; it != edge_triangles_.end() && it->first == key; ++it) sum += face_normal(it->second);
  } else {
    const std::uint32_t v = triangles_[3 * t + c.index];
    for (std::uint32_t k = vertex_offsets_[v]; k < vertex_offsets_[v + 1]; ++k) {
      const std::uint32_t f = vertex_triangles_[k];
      const std::uint32_t* corner = &triangles_[3 * static_cast<std::size_t>(f)];
      const int at = corner[0] == v ? 0 : corner[1] == v ? 1 : 2;
      const double angle =
          corner_angle(relative_[corner[at]], relative_[corner[(at + 1) % 3]], relative_[corner[(at + 2) % 3]]);
      sum += face_normal(f) * angle;
    }
  }
  const double len = norm(sum);
  return len > 0.0 ? sum * (1.0 / len) : face_normal(t);
}

MeshSide MeshSideOracle::side(const deform::PointModel& model, const Vec3& q) {
  if (model.size() != point_count_) {
    throw std::invalid_argument("mesh oracle: model has " + std::to_string(model.size()) + " points, mesh " +
                                std::to_string(point_count_));
  }
  // Everything relative to q: the winding sum's vectors, and the distance's closest point of
  // the origin, computed once per vertex rather than once per corner.
  relative_.resize(point_count_);
  length_.resize(point_count_);
  for (std::size_t i = 0; i < point_count_; ++i) {
    relative_[i] = model.position(i) - q;
    length_[i] = norm(relative_[i]);
  }
  const std::size_t nt = triangle_count();
  const Vec3 origin;
  double best = std::numeric_limits<double>::infinity();
  std::size_t nearest = 0;
  TriangleClosest nearest_point;
  double omega = 0.0;
  for (std::size_t t = 0; t < nt; ++t) {
    const std::uint32_t ia = triangles_[3 * t], ib = triangles_[3 * t + 1], ic = triangles_[3 * t + 2];
    const Vec3& a = relative_[ia];
    const Vec3& b = relative_[ib];
    const Vec3& c = relative_[ic];
    if (closed_) omega += solid_angle_of(a, b, c, length_[ia], length_[ib], length_[ic]);
    // Every point of a triangle is within its longest edge of each corner, so the triangle is no
    // nearer than its farthest corner less that edge: most triangles are skipped on that.
    const double margin = std::max({length_[ia], length_[ib], length_[ic]}) - best;
    if (margin > 0.0 && margin * margin >= std::max({squared_norm(b - a), squared_norm(c - b), squared_norm(a - c)})) {
      continue;
    }
    const TriangleClosest x = closest_on_triangle(origin, a, b, c);
    const double d = norm(x.point);
    if (d < best) best = d, nearest = t, nearest_point = x;
  }

  MeshSide r;
  r.distance = best;
  r.triangle = static_cast<std::uint32_t>(nearest);
  r.closest = nearest_point.point + q;
  if (closed_) {
    r.winding = omega / (4.0 * std::numbers::pi);
    r.inside = r.winding > 0.5;
    r.outward_normal = face_normal(nearest);
  } else {
    r.outward_normal = pseudo_normal(nearest, nearest_point);
    // nearest_point is relative to q, so q - nearest is its negative.
    r.inside = dot(nearest_point.point * -1.0, r.outward_normal) < 0.0;
  }
  r.side = r.inside ? -r.distance : r.distance;
  return r;
}

}  // namespace sculpt::tools::check
