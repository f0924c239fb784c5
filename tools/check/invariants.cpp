#include "invariants.hpp"

#include <algorithm>
#include <cmath>

namespace sculpt::tools::check {

using deform::Vec3;

Vec3 Similarity::rotate(const Vec3& v) const {
  return {r[0][0] * v.x + r[0][1] * v.y + r[0][2] * v.z, r[1][0] * v.x + r[1][1] * v.y + r[1][2] * v.z,
          r[2][0] * v.x + r[2][1] * v.y + r[2][2] * v.z};
}

Vec3 Similarity::unrotate(const Vec3& v) const {
  return {r[0][0] * v.x + r[1][0] * v.y + r[2][0] * v.z, r[0][1] * v.x + r[1][1] * v.y + r[2][1] * v.z,
          r[0][2] * v.x + r[1][2] * v.y + r[2][2] * v.z};
}

Similarity Similarity::after(const Similarity& inner) const {
  Similarity out;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      out.r[i][j] = 0.0;
      for (int m = 0; m < 3; ++m) out.r[i][j] += r[i][m] * inner.r[m][j];
    }
  }
  out.scale = scale * inner.scale;
  out.shift = apply(inner.shift);
  return out;
}

Similarity Similarity::scaling(double s) {
  Similarity t;
  t.scale = s;
  return t;
}

Similarity Similarity::rigid(const Vec3& axis, double angle, const Vec3& shift) {
  const Vec3 a = deform::normalized(axis);
  const double c = std::cos(angle), s = std::sin(angle), one_minus_c = 1.0 - c;
  Similarity t;
  t.r[0][0] = c + a.x * a.x * one_minus_c;
  t.r[0][1] = a.x * a.y * one_minus_c - a.z * s;
  t.r[0][2] = a.x * a.z * one_minus_c + a.y * s;
  t.r[1][0] = a.y * a.x * one_minus_c + a.z * s;
  t.r[1][1] = c + a.y * a.y * one_minus_c;
  t.r[1][2] = a.y * a.z * one_minus_c - a.x * s;
  t.r[2][0] = a.z * a.x * one_minus_c - a.y * s;
  t.r[2][1] = a.z * a.y * one_minus_c + a.x * s;
  t.r[2][2] = c + a.z * a.z * one_minus_c;
  t.shift = shift;
  return t;
}

deform::PointModel transformed(const deform::PointModel& model, const Similarity& t) {
  deform::PointModel out = model;
  for (std::size_t i = 0; i < model.size(); ++i) {
    out.set_position(i, t.apply(model.position(i)));
    if (model.has_normals()) out.set_normal(i, t.rotate(model.normal(i)));
  }
  return out;
}

double relative_deviation(const deform::PointModel& initial, const deform::PointModel& base,
                          const deform::PointModel& variant_initial, const deform::PointModel& variant,
                          const Similarity& t, double floor) {
  double largest = 0.0, worst = 0.0;
  for (std::size_t i = 0; i < base.size(); ++i) {
    const Vec3 moved = base.position(i) - initial.position(i);
    largest = std::max(largest, norm(moved));
    const Vec3 variant_moved = t.unrotate(variant.position(i) - variant_initial.position(i)) * (1.0 / t.scale);
    const double d = norm(variant_moved - moved);
    if (!std::isfinite(d)) return HUGE_VAL;  // a non-finite point is the worst deviation there is
    worst = std::max(worst, d);
  }
  return worst / std::max(largest, floor);
}

double coordinate_magnitude(const deform::PointModel& model, const Similarity& t) {
  double largest = 0.0;
  for (std::size_t i = 0; i < model.size(); ++i) {
    largest =
        std::max({largest, double{std::abs(model.x[i])}, double{std::abs(model.y[i])}, double{std::abs(model.z[i])}});
  }
  return largest / t.scale;
}

}  // namespace sculpt::tools::check
