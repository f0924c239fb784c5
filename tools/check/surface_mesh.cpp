#include "surface_mesh.hpp"

extern "C" {
#include <libqhull_r/qhull_ra.h>
}

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace sculpt::tools::check {

using deform::Vec3;

namespace {

// One Qhull run over `coordinates` (dim per point) with `options`; calls `facet` with the point
// indices and the facet record of every facet. Qhull's state lives here and is freed here, so
// an exception from `facet` cannot leak it.
template <typename Each>
void run_qhull(std::vector<double> coordinates, int dim, const char* options, Each facet_fn) {
  qhT state;
  qhT* qh = &state;
  QHULL_LIB_CHECK
  qh_zero(qh, stderr);
  std::string command = std::string("qhull ") + options;
  const int points = static_cast<int>(coordinates.size() / static_cast<std::size_t>(dim));
  const int status = qh_new_qhull(qh, dim, points, coordinates.data(), False, command.data(), nullptr, stderr);
  std::string error;
  if (status != 0) {
    error = "Qhull (" + command + ") failed with status " + std::to_string(status);
  } else {
    facetT* facet = nullptr;
    vertexT* vertex = nullptr;
    vertexT** vertexp = nullptr;
    FORALLfacets {
      std::vector<std::uint32_t> ids;
      FOREACHvertex_(facet->vertices) ids.push_back(static_cast<std::uint32_t>(qh_pointid(qh, vertex->point)));
      facet_fn(ids, *facet);
    }
  }
  int long_blocks = 0, long_bytes = 0;
  qh_freeqhull(qh, !qh_ALL);
  qh_memfreeshort(qh, &long_blocks, &long_bytes);
  if (!error.empty()) throw std::runtime_error(error);
}

std::size_t count_unused(const std::vector<std::uint32_t>& triangles, std::size_t n) {
  std::vector<bool> used(n, false);
  for (std::uint32_t i : triangles) used[i] = true;
  std::size_t unused = 0;
  for (bool u : used) unused += !u;
  return unused;
}

// Appends triangle (a, b, c) wound so that its normal has a positive component along `out`.
void push_oriented(std::vector<std::uint32_t>& triangles, const deform::PointModel& m, std::uint32_t a, std::uint32_t b,
                   std::uint32_t c, const Vec3& out) {
  const Vec3 n = cross(m.position(b) - m.position(a), m.position(c) - m.position(a));
  if (dot(n, out) < 0.0) std::swap(b, c);
  triangles.insert(triangles.end(), {a, b, c});
}

}  // namespace

SurfaceMesh convex_hull_mesh(const deform::PointModel& model) {
  std::vector<double> xyz;
  xyz.reserve(3 * model.size());
  for (std::size_t i = 0; i < model.size(); ++i) {
    const Vec3 p = model.position(i);
    xyz.insert(xyz.end(), {p.x, p.y, p.z});
  }
  SurfaceMesh mesh;
  // Qt: merged (coplanar) facets come out as triangles. Each facet's normal from Qhull points
  // out of the hull; the winding is chosen to agree with it rather than read from Qhull's flags.
  run_qhull(std::move(xyz), 3, "Qt", [&](const std::vector<std::uint32_t>& ids, const facetT& f) {
    if (ids.size() != 3) throw std::runtime_error("Qhull gave a facet of " + std::to_string(ids.size()) + " vertices");
    push_oriented(mesh.triangles, model, ids[0], ids[1], ids[2], {f.normal[0], f.normal[1], f.normal[2]});
  });
  mesh.unused_points = count_unused(mesh.triangles, model.size());
  return mesh;
}

SurfaceMesh sheet_mesh(const deform::PointModel& model, const Vec3& outside) {
  const Vec3 n = normalized(outside);
  const Vec3 u = normalized(cross(n, std::abs(n.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0}));
  const Vec3 v = cross(n, u);
  std::vector<double> uv;
  uv.reserve(2 * model.size());
  for (std::size_t i = 0; i < model.size(); ++i) {
    const Vec3 p = model.position(i);
    uv.insert(uv.end(), {dot(p, u), dot(p, v)});
  }
  SurfaceMesh mesh;
  // d: Delaunay (the lower hull of the points lifted onto a paraboloid); Qbb scales the lift so
  // that a grid's cocircular points are resolved the same at every size; Qt triangulates them.
  run_qhull(std::move(uv), 2, "d Qbb Qt", [&](const std::vector<std::uint32_t>& ids, const facetT& f) {
    if (f.upperdelaunay) return;
    if (ids.size() != 3)
      throw std::runtime_error("Qhull gave a triangle of " + std::to_string(ids.size()) + " vertices");
    push_oriented(mesh.triangles, model, ids[0], ids[1], ids[2], n);
  });
  mesh.unused_points = count_unused(mesh.triangles, model.size());
  return mesh;
}

}  // namespace sculpt::tools::check
