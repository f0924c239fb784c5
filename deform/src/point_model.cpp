#include "sculpt/deform/point_model.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "coordinate_range.hpp"

namespace sculpt::deform {

void PointModel::set_position(std::size_t i, const Vec3& p) {
  x[i] = static_cast<float>(p.x);
  y[i] = static_cast<float>(p.y);
  z[i] = static_cast<float>(p.z);
}

void PointModel::set_normal(std::size_t i, const Vec3& n) {
  nx[i] = static_cast<float>(n.x);
  ny[i] = static_cast<float>(n.y);
  nz[i] = static_cast<float>(n.z);
}

void PointModel::resize(std::size_t n, bool with_normals, bool with_colors, bool with_alpha) {
  x.resize(n);
  y.resize(n);
  z.resize(n);
  if (with_normals || has_normals()) {
    nx.resize(n);
    ny.resize(n);
    nz.resize(n);
  }
  if (with_colors || has_colors()) {
    red.resize(n);
    green.resize(n);
    blue.resize(n);
  }
  if (with_alpha || has_alpha()) alpha.resize(n, 255);
}

void PointModel::push_back(const Vec3& p) {
  resize(size() + 1, false, false);
  set_position(size() - 1, p);
}

void PointModel::clear_normals() {
  nx.clear();
  ny.clear();
  nz.clear();
}

void PointModel::validate() const {
  const std::size_t n = size();
  auto check = [n](std::size_t got, bool optional, const char* what) {
    if (got != n && !(optional && got == 0)) {
      throw std::invalid_argument(std::string("point model: attribute '") + what + "' has " + std::to_string(got) +
                                  " entries for " + std::to_string(n) + " points");
    }
  };
  check(y.size(), false, "y");
  check(z.size(), false, "z");
  check(nx.size(), true, "nx");
  check(ny.size(), nx.empty(), "ny");
  check(nz.size(), nx.empty(), "nz");
  check(red.size(), true, "red");
  check(green.size(), red.empty(), "green");
  check(blue.size(), red.empty(), "blue");
  check(alpha.size(), true, "alpha");
  if (triangles.size() % 3 != 0) {
    throw std::invalid_argument("point model: triangle index count is not a multiple of 3");
  }
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    if (triangles[t] >= n) {
      throw std::invalid_argument("point model: triangle " + std::to_string(t / 3) + " refers to point " +
                                  std::to_string(triangles[t]) + " of " + std::to_string(n));
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    const std::string problem = coordinate_range_problem(x[i], y[i], z[i], "point", i);
    if (!problem.empty()) throw std::invalid_argument("point model: " + problem);
  }
}

PointModel::Box PointModel::bounding_box() const noexcept {
  if (empty()) return {};
  auto span = [](const std::vector<float>& v) {
    const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
    return std::pair<double, double>{*lo, *hi};
  };
  const auto [x_lo, x_hi] = span(x);
  const auto [y_lo, y_hi] = span(y);
  const auto [z_lo, z_hi] = span(z);
  return {{x_lo, y_lo, z_lo}, {x_hi, y_hi, z_hi}};
}

double PointModel::bounding_box_diagonal() const {
  const Box box = bounding_box();
  return norm(box.hi - box.lo);
}

Vec3 PointModel::bounding_box_centre() const {
  const Box box = bounding_box();
  return 0.5 * (box.lo + box.hi);
}

}  // namespace sculpt::deform
