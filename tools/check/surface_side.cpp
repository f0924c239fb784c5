#include "surface_side.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

#include <algorithm>
#include <cmath>

namespace sculpt::tools::check {

using deform::Vec3;

Vec3 centroid(const deform::PointModel& model) {
  Vec3 sum;
  for (std::size_t i = 0; i < model.size(); ++i) sum += model.position(i);
  return model.empty() ? Vec3{} : sum * (1.0 / static_cast<double>(model.size()));
}

// The rotation that best maps the neighbourhood's undeformed positions onto its current ones
// (Kabsch: the SVD of their cross-covariance), applied to `v`.
Vec3 SurfaceSideOracle::carried_by_rotation(const deform::PointModel& reference, const deform::PointModel& model,
                                            std::size_t k, const Vec3& v) const {
  auto at = [](const deform::PointModel& m, std::uint32_t i) {
    const Vec3 p = m.position(i);
    return Eigen::Vector3d(p.x, p.y, p.z);
  };
  Eigen::Vector3d rm = Eigen::Vector3d::Zero(), dm = Eigen::Vector3d::Zero();
  for (std::size_t j = 0; j < k; ++j) {
    rm += at(reference, scratch_[j].second);
    dm += at(model, scratch_[j].second);
  }
  rm /= static_cast<double>(k);
  dm /= static_cast<double>(k);
  Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
  for (std::size_t j = 0; j < k; ++j) {
    h += (at(reference, scratch_[j].second) - rm) * (at(model, scratch_[j].second) - dm).transpose();
  }
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(h, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
  d(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0.0 ? -1.0 : 1.0;
  const Eigen::Vector3d r = svd.matrixV() * d * svd.matrixU().transpose() * Eigen::Vector3d(v.x, v.y, v.z);
  return {r.x(), r.y(), r.z()};
}

PlaneSide SurfaceSideOracle::side(const deform::PointModel& model, const Vec3& q, const Outside& outside) {
  const std::size_t n = model.size();
  const std::size_t k = std::min(k_, n);
  scratch_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    scratch_[i] = {squared_norm(model.position(i) - q), static_cast<std::uint32_t>(i)};
  }
  // Ties broken by index so that the answer does not depend on the selection's internals.
  std::nth_element(scratch_.begin(), scratch_.begin() + static_cast<std::ptrdiff_t>(k - 1), scratch_.end());
  std::sort(scratch_.begin(), scratch_.begin() + static_cast<std::ptrdiff_t>(k));

  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (std::size_t j = 0; j < k; ++j) {
    const Vec3 p = model.position(scratch_[j].second);
    mean += Eigen::Vector3d(p.x, p.y, p.z);
  }
  mean /= static_cast<double>(k);
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (std::size_t j = 0; j < k; ++j) {
    const Vec3 p = model.position(scratch_[j].second);
    const Eigen::Vector3d d = Eigen::Vector3d(p.x, p.y, p.z) - mean;
    cov += d * d.transpose();
  }

  // The outside direction at this place: away from the centroid, or the sheet's fixed side.
  const deform::PointModel& shape = outside.reference ? *outside.reference : model;
  Eigen::Vector3d out;
  if (outside.kind == Outside::Kind::kAwayFromCentroid) {
    const Vec3 c = centroid(shape);
    Eigen::Vector3d shape_mean = Eigen::Vector3d::Zero();
    for (std::size_t j = 0; j < k; ++j) {
      const Vec3 p = shape.position(scratch_[j].second);
      shape_mean += Eigen::Vector3d(p.x, p.y, p.z);
    }
    out = shape_mean / static_cast<double>(k) - Eigen::Vector3d(c.x, c.y, c.z);
  } else {
    out = Eigen::Vector3d(outside.direction.x, outside.direction.y, outside.direction.z);
  }
  if (outside.reference && k >= 3) {
    const Vec3 carried = carried_by_rotation(*outside.reference, model, k, {out.x(), out.y(), out.z()});
    out = Eigen::Vector3d(carried.x, carried.y, carried.z);
  }
  if (out.norm() > 0.0) out.normalize();

  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  const Eigen::Vector3d values = eig.eigenvalues();  // ascending
  const double largest = values(2);
  // Relative to the spread of the neighbourhood; float coordinates give ~1e-14 noise here.
  const double flat = 1e-10 * largest;
  Eigen::Vector3d normal;
  if (!(largest > 0.0)) {
    normal = out;  // one point, or all coincident: the plane normal to the outside
  } else if (values(1) <= flat) {
    // Collinear: every plane through the row fits; take the one whose normal is the outside
    // direction with the row's own direction removed.
    const Eigen::Vector3d along = eig.eigenvectors().col(2);
    normal = out - along * along.dot(out);
    normal = normal.norm() > 0.0 ? Eigen::Vector3d(normal.normalized()) : out;
  } else {
    normal = eig.eigenvectors().col(0);
  }
  if (normal.dot(out) < 0.0) normal = -normal;

  PlaneSide r;
  r.normal = {normal.x(), normal.y(), normal.z()};
  r.centre = {mean.x(), mean.y(), mean.z()};
  // Measured from the nearest point, not the mean: the mean of k points sits off the surface by
  // its curvature (inside a convex cap, above the bottom of a narrow pit), the nearest point is on it.
  const Vec3 a = model.position(scratch_[0].second);
  r.side = normal.dot(Eigen::Vector3d(q.x - a.x, q.y - a.y, q.z - a.z));
  r.nearest = scratch_[0].second;
  return r;
}

}  // namespace sculpt::tools::check
