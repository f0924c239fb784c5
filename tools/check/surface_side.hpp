#pragma once
// An inside/outside oracle that does not trust the deformer: the side of a point is read off the
// geometric surface of the model as it is now (a PCA plane of the k nearest points), oriented by
// what is known about the shape (its outside), never by the normals the deformer carries.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "sculpt/deform/point_model.hpp"
#include "sculpt/deform/vec3.hpp"

namespace sculpt::tools::check {

/// What is known to be outside, independent of any normal stored in the model.
struct Outside {
  enum class Kind {
    kAwayFromCentroid,  ///< closed, convex-ish shapes: outside is away from the points' centroid
    kDirection,         ///< open sheets: outside is along a fixed direction
  };
  Kind kind = Kind::kAwayFromCentroid;
  deform::Vec3 direction{0.0, 0.0, 1.0};  ///< for kDirection (need not be unit)
  /// The undeformed model (same points, same order), or null. When set, the outside is read
  /// there (where the rule above holds) and carried to the deformed neighbourhood by its best-fit
  /// rotation: a pit pushed past the centroid still faces up, as its material does.
  const deform::PointModel* reference = nullptr;
};

/// The local surface near a query point.
struct PlaneSide {
  /// Signed distance along the plane's outward normal from the nearest point: negative inside.
  double side = 0.0;
  deform::Vec3 normal;        ///< outward unit normal of the fitted plane
  deform::Vec3 centre;        ///< mean of the k nearest points (a point of the plane)
  std::uint32_t nearest = 0;  ///< the nearest model point to the query
};

/// Brute-force k nearest points and a PCA plane through them. Exact, slow (O(n) a query), and
/// sharing nothing with deform's index or normals: that is the point of it.
class SurfaceSideOracle {
 public:
  explicit SurfaceSideOracle(std::size_t k = 12) : k_(k < 1 ? 1 : k) {}

  /// The side of `q` against `model`'s surface near q. Degenerate neighbourhoods still give an
  /// answer: collinear points (a row) give the plane through the row that faces the outside, a
  /// single point (or all coincident) the plane through it normal to the outside.
  /// The model must not be empty.
  PlaneSide side(const deform::PointModel& model, const deform::Vec3& q, const Outside& outside);

  std::size_t k() const { return k_; }

 private:
  deform::Vec3 carried_by_rotation(const deform::PointModel& reference, const deform::PointModel& model, std::size_t k,
                                   const deform::Vec3& v) const;
  std::size_t k_;
  std::vector<std::pair<double, std::uint32_t>> scratch_;
};

/// Centroid of the model's points (for Outside::kAwayFromCentroid).
deform::Vec3 centroid(const deform::PointModel& model);

}  // namespace sculpt::tools::check
