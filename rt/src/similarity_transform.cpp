#include "sculpt/rt/similarity_transform.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace sculpt::rt {
namespace {

using Vec3 = std::array<double, 3>;

// Landmarks whose scatter has a second eigenvalue below this fraction of the first lie on a
// line (to within 1e-6 of their extent): the rotation about that line is then undetermined.
constexpr double kCollinearTolerance = 1e-12;

[[noreturn]] void fail(const std::string& what) { throw std::invalid_argument(what); }

void check_scale_translation(double scale, const Vec3& translation) {
  if (!std::isfinite(scale) || scale <= 0.0) {
    std::ostringstream s;
    s << "similarity transform: the scale must be finite and > 0, got " << scale;
    fail(s.str());
  }
  for (double c : translation) {
    if (!std::isfinite(c)) fail("similarity transform: the translation is not finite");
  }
}

Matrix3 multiply(const Matrix3& a, const Matrix3& b) noexcept {
  Matrix3 m{};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      m[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
    }
  }
  return m;
}

Matrix3 transpose(const Matrix3& a) noexcept {
  Matrix3 m{};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) m[i][j] = a[j][i];
  }
  return m;
}

Vec3 multiply(const Matrix3& a, const Vec3& v) noexcept {
  return {a[0][0] * v[0] + a[0][1] * v[1] + a[0][2] * v[2], a[1][0] * v[0] + a[1][1] * v[1] + a[1][2] * v[2],
          a[2][0] * v[0] + a[2][1] * v[1] + a[2][2] * v[2]};
}

double determinant(const Matrix3& a) noexcept {
  return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
         a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
}

Matrix3 matrix_of_unit_quaternion(double w, double x, double y, double z) noexcept {
  return {{{1.0 - 2.0 * (y * y + z * z), 2.0 * (x * y - w * z), 2.0 * (x * z + w * y)},
           {2.0 * (x * y + w * z), 1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z - w * x)},
           {2.0 * (x * z - w * y), 2.0 * (y * z + w * x), 1.0 - 2.0 * (x * x + y * y)}}};
}

// Scatter eigenvalues in decreasing order: their ratios say whether the points span a plane.
Eigen::Vector3d scatter_eigenvalues(std::span<const Vec3> points, const Eigen::Vector3d& mean) {
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const Vec3& p : points) {
    const Eigen::Vector3d d = Eigen::Vector3d(p[0], p[1], p[2]) - mean;
    scatter += d * d.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(scatter, Eigen::EigenvaluesOnly);
  const Eigen::Vector3d ascending = solver.eigenvalues();
  return {ascending[2], ascending[1], ascending[0]};
}

Eigen::Vector3d mean_of(std::span<const Vec3> points) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const Vec3& p : points) sum += Eigen::Vector3d(p[0], p[1], p[2]);
  return sum / static_cast<double>(points.size());
}

void check_spread(std::span<const Vec3> points, const Eigen::Vector3d& mean, const char* which) {
  const Eigen::Vector3d lambda = scatter_eigenvalues(points, mean);
  if (!(lambda[0] > 0.0)) {
    fail(std::string("calibrate: the ") + which + " landmarks all coincide");
  }
  if (!(lambda[1] > kCollinearTolerance * lambda[0])) {
    fail(std::string("calibrate: the ") + which +
         " landmarks are collinear; the rotation about their line is undetermined "
         "(use at least 3 landmarks not on one line)");
  }
}

}  // namespace

SimilarityTransform SimilarityTransform::from_scale_rotation_translation(double scale, const Quaternion& q,
                                                                         const Vec3& translation) {
  check_scale_translation(scale, translation);
  if (!std::isfinite(q.w) || !std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z)) {
    fail("similarity transform: the quaternion is not finite");
  }
  const double norm = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
  if (!(std::abs(norm - 1.0) <= kUnitTolerance)) {
    std::ostringstream s;
    s << "similarity transform: the quaternion (w,x,y,z) = (" << q.w << ", " << q.x << ", " << q.y << ", " << q.z
      << ") has norm " << norm << ", not 1 within " << kUnitTolerance;
    fail(s.str());
  }
  return {scale, matrix_of_unit_quaternion(q.w / norm, q.x / norm, q.y / norm, q.z / norm), translation};
}

SimilarityTransform SimilarityTransform::from_scale_rotation_translation(double scale, const AxisAngle& r,
                                                                         const Vec3& translation) {
  check_scale_translation(scale, translation);
  if (!std::isfinite(r.angle) || !std::isfinite(r.axis[0]) || !std::isfinite(r.axis[1]) || !std::isfinite(r.axis[2])) {
    fail("similarity transform: the axis-angle rotation is not finite");
  }
  const double length = std::sqrt(r.axis[0] * r.axis[0] + r.axis[1] * r.axis[1] + r.axis[2] * r.axis[2]);
  if (r.angle == 0.0) return {scale, SimilarityTransform().rotation_, translation};
  if (!(length > 0.0)) fail("similarity transform: the rotation axis is zero but the angle is not");
  // Through the quaternion, which is exactly orthonormal up to rounding for any angle.
  const double half = 0.5 * r.angle;
  const double s = std::sin(half) / length;
  return {scale, matrix_of_unit_quaternion(std::cos(half), r.axis[0] * s, r.axis[1] * s, r.axis[2] * s), translation};
}

SimilarityTransform SimilarityTransform::from_scale_rotation_translation(double scale, const Matrix3& r,
                                                                         const Vec3& translation) {
  check_scale_translation(scale, translation);
  for (const auto& row : r) {
    for (double c : row) {
      if (!std::isfinite(c)) fail("similarity transform: the rotation matrix is not finite");
    }
  }
  const Matrix3 rtr = multiply(transpose(r), r);
  double off = 0.0;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) off = std::max(off, std::abs(rtr[i][j] - (i == j ? 1.0 : 0.0)));
  }
  if (!(off <= kOrthonormalTolerance)) {
    std::ostringstream s;
    s << "similarity transform: the rotation matrix is not orthonormal (|R^T R - I| = " << off << ")";
    fail(s.str());
  }
  if (!(std::abs(determinant(r) - 1.0) <= kOrthonormalTolerance)) {
    fail(
        "similarity transform: the rotation matrix has determinant -1 (a reflection), not a "
        "rotation");
  }
  return {scale, r, translation};
}

Vec3 SimilarityTransform::apply(const Vec3& point) const noexcept {
  const Vec3 r = multiply(rotation_, point);
  return {scale_ * r[0] + translation_[0], scale_ * r[1] + translation_[1], scale_ * r[2] + translation_[2]};
}

Vec3 SimilarityTransform::apply_vector(const Vec3& vector) const noexcept {
  const Vec3 r = multiply(rotation_, vector);
  return {scale_ * r[0], scale_ * r[1], scale_ * r[2]};
}

SimilarityTransform SimilarityTransform::compose(const SimilarityTransform& first) const noexcept {
  // s2 R2 (s1 R1 x + t1) + t2 = (s2 s1) (R2 R1) x + (s2 R2 t1 + t2)
  return {scale_ * first.scale_, multiply(rotation_, first.rotation_), apply(first.translation_)};
}

SimilarityTransform SimilarityTransform::inverse() const noexcept {
  const Matrix3 rt = transpose(rotation_);
  const double inv = 1.0 / scale_;
  const Vec3 back = multiply(rt, translation_);
  return {inv, rt, {-inv * back[0], -inv * back[1], -inv * back[2]}};
}

Quaternion SimilarityTransform::quaternion() const noexcept {
  // Shepperd: divide by the largest of the four candidate components, never a small one.
  const Matrix3& m = rotation_;
  const double trace = m[0][0] + m[1][1] + m[2][2];
  Quaternion q;
  if (trace >= m[0][0] && trace >= m[1][1] && trace >= m[2][2]) {
    const double r = std::sqrt(1.0 + trace);
    q = {0.5 * r, (m[2][1] - m[1][2]) / (2.0 * r), (m[0][2] - m[2][0]) / (2.0 * r), (m[1][0] - m[0][1]) / (2.0 * r)};
  } else if (m[0][0] >= m[1][1] && m[0][0] >= m[2][2]) {
    const double r = std::sqrt(1.0 + m[0][0] - m[1][1] - m[2][2]);
    q = {(m[2][1] - m[1][2]) / (2.0 * r), 0.5 * r, (m[0][1] + m[1][0]) / (2.0 * r), (m[0][2] + m[2][0]) / (2.0 * r)};
  } else if (m[1][1] >= m[2][2]) {
    const double r = std::sqrt(1.0 - m[0][0] + m[1][1] - m[2][2]);
    q = {(m[0][2] - m[2][0]) / (2.0 * r), (m[0][1] + m[1][0]) / (2.0 * r), 0.5 * r, (m[1][2] + m[2][1]) / (2.0 * r)};
  } else {
    const double r = std::sqrt(1.0 - m[0][0] - m[1][1] + m[2][2]);
    q = {(m[1][0] - m[0][1]) / (2.0 * r), (m[0][2] + m[2][0]) / (2.0 * r), (m[1][2] + m[2][1]) / (2.0 * r), 0.5 * r};
  }
  const double n = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
  const double sign = q.w < 0.0 ? -1.0 : 1.0;
  return {sign * q.w / n, sign * q.x / n, sign * q.y / n, sign * q.z / n};
}

Calibration calibrate_umeyama(std::span<const Vec3> glove, std::span<const Vec3> model) {
  if (glove.size() != model.size()) {
    fail("calibrate: " + std::to_string(glove.size()) + " glove landmarks but " + std::to_string(model.size()) +
         " model landmarks; they must be pairs");
  }
  if (glove.size() < 3) {
    fail("calibrate: " + std::to_string(glove.size()) + " landmark pairs; at least 3 are needed");
  }
  for (std::size_t i = 0; i < glove.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      if (!std::isfinite(glove[i][k]) || !std::isfinite(model[i][k])) {
        fail("calibrate: landmark pair " + std::to_string(i) + " has a non-finite coordinate");
      }
    }
  }
  const Eigen::Vector3d mu_x = mean_of(glove);
  const Eigen::Vector3d mu_y = mean_of(model);
  check_spread(glove, mu_x, "glove");
  check_spread(model, mu_y, "model");

  // Umeyama (1991), eqs. 38-42, with x = glove, y = model: Sigma_xy = 1/n sum (y - mu_y)(x -
  // mu_x)^T.
  const double n = static_cast<double>(glove.size());
  Eigen::Matrix3d sigma_xy = Eigen::Matrix3d::Zero();
  double variance_x = 0.0;
  for (std::size_t i = 0; i < glove.size(); ++i) {
    const Eigen::Vector3d dx = Eigen::Vector3d(glove[i][0], glove[i][1], glove[i][2]) - mu_x;
    const Eigen::Vector3d dy = Eigen::Vector3d(model[i][0], model[i][1], model[i][2]) - mu_y;
    sigma_xy += dy * dx.transpose();
    variance_x += dx.squaredNorm();
  }
  sigma_xy /= n;
  variance_x /= n;

  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(sigma_xy, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Matrix3d& u = svd.matrixU();
  const Eigen::Matrix3d& v = svd.matrixV();
  // The reflection fix: when U V^T would be a reflection, flip the direction of the smallest
  // singular value. This also covers planar landmarks (3 points), where that value is 0 and
  // the sign of det(U) det(V) is arbitrary.
  Eigen::Vector3d sign(1.0, 1.0, 1.0);
  if (u.determinant() * v.determinant() < 0.0) sign[2] = -1.0;
  const Eigen::Matrix3d r = u * sign.asDiagonal() * v.transpose();
  const double scale = svd.singularValues().dot(sign) / variance_x;
  if (!(scale > 0.0) || !std::isfinite(scale)) {
    fail("calibrate: the landmarks give no positive scale (model and glove do not correspond)");
  }
  const Eigen::Vector3d t = mu_y - scale * r * mu_x;

  Matrix3 rotation{};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) rotation[i][j] = r(i, j);
  }
  Calibration c;
  c.transform = SimilarityTransform::from_scale_rotation_translation(scale, rotation, {t[0], t[1], t[2]});
  double sum_sq = 0.0;
  for (std::size_t i = 0; i < glove.size(); ++i) {
    const Vec3 p = c.transform.apply(glove[i]);
    const double e = std::hypot(p[0] - model[i][0], p[1] - model[i][1], p[2] - model[i][2]);
    sum_sq += e * e;
    c.max_residual = std::max(c.max_residual, e);
  }
  c.rms_residual = std::sqrt(sum_sq / n);
  return c;
}

}  // namespace sculpt::rt
