#pragma once
// The localised region Omega of thesis 4.4.2: only its points move, and a band along its
// border is pinned with u0 = 0 so the surface does not tear.

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "sculpt/deform/ball_cache.hpp"
#include "sculpt/deform/point_index.hpp"
#include "sculpt/deform/point_model.hpp"
#include "sculpt/deform/point_set.hpp"

namespace sculpt::deform {

struct RegionSettings {
  enum class Kind {
    kGlobal,   ///< every point moves; no border
    kRadius,   ///< the union of balls of `radius` around each contact point
    kIndices,  ///< a fixed set of point indices
  };
  Kind kind = Kind::kGlobal;
  double radius = 0.0;
  std::vector<std::uint32_t> indices;  ///< for kIndices
  /// Width of the pinned band inside the border; 0 means "the contact's bc radius".
  double border_width = 0.0;
  /// Weight of the whole band against one contact neighbourhood in the least squares. A single
  /// Kelvin source cannot hold the band exactly at zero and move the contact onto the probe;
  /// with weight 1 the band counts as much as the contact, so the contact still nearly reaches
  /// the probe and the band's residual motion is reported, not hidden.
  double border_weight = 1.0;
  /// A kRadius frame whose region holds more than 1/kRegionPointCost of the model moves every
  /// point instead, as the global frame: a region's point costs about that many of a global
  /// frame's (gathered and scattered, found by queries, its band's rows in the solve), so the
  /// global frame is then the cheaper one, and exact where the region pins its band. Off: only
  /// the region's points move, whatever that costs (nothing outside it ever moves).
  bool global_when_cheaper = true;
};

/// The width of the pinned band inside a region's border: the setting, or bc_radius when it is
/// unset (0), so that a contact's neighbourhood and the band have the same scale by default.
double region_border_width(const RegionSettings& settings, double bc_radius);

/// The radius a kRadius region must exceed: the contact's neighbourhood (bc_radius) and the
/// pinned band inside the border must both fit, or the frame would pin the very points it asks
/// to move. Region's constructor refuses a radius not above it.
double smallest_region_radius(const RegionSettings& settings, double bc_radius);

/// What a region frame's moved point costs over a global frame's point, measured here (see
/// RegionSettings::global_when_cheaper): on the bundled sphere, one and three fingers, a region
/// frame cost as much as the global one at 14-16 % of the points; on the 100k dragon's
/// five-finger press 32 ns per moved point against 4.9 ns per point in the global frame.
inline constexpr std::size_t kRegionPointCost = 6;

/// The points a frame moves and the band it pins. Buffers are reserved at construction for the
/// whole model, so build() never allocates.
class Region {
 public:
  /// Validates the settings (throws std::invalid_argument naming the bad value) and reserves.
  /// For kIndices the border band is found here, once.
  Region(const RegionSettings& settings, const PointModel& model, const PointIndex& index, double bc_radius);

  /// Collects the region and its border for this frame's contact points. A kRadius region one
  /// of whose balls, less the band, holds the whole model (its box, below) is every point with no
  /// band: the frame is then global() and nothing is collected, since a global frame moves the
  /// same points by the same bits without the queries, the union and the scattered reads (on
  /// the bundled sphere a region holding all of it took 2.3 times the global frame). A region
  /// whose balls turn out to hold every point deep inside is global() too, its queries paid, and
  /// so is one holding more than 1/kRegionPointCost of the points (global_when_cheaper).
  /// When the last build's balls found many points for the model's size, every point is tested
  /// instead, in the order of the arrays (scan_pays()): the same points and band, ascending,
  /// whichever way.
  void build(const PointModel& model, const PointIndex& index, double drift, std::span<const Vec3> contacts);

  /// Every point moves: a kGlobal region, or a kRadius region whose last build() held the model
  /// or found the global frame the cheaper.
  bool global() const { return settings_.kind == RegionSettings::Kind::kGlobal || moves_model_; }
  /// The model is the one this region was constructed on again (the deformer's restore): its
  /// box as measured then, without a pass over the points (one more pass over a large model
  /// before a frame left the frame's data out of the caches: the bench's 437k press, which
  /// restores before every frame, 0.125 to 0.167 ms).
  void back_to_base() noexcept {
    box_lo_ = base_lo_;
    box_hi_ = base_hi_;
    moved_since_measure_ = 0.0;
    balls_.forget();
  }
  /// The model's positions were written from outside the frames (add_move() was not told):
  /// measures its box again and forgets the balls kept. Set-up time: a pass over the points.
  void remeasure(const PointModel& model) noexcept {
    measure_model(model);
    balls_.forget();
  }

  /// Every point moved at most `distance` more (the deformer's stored move of a kept frame).
  /// NaN or infinity: no ball holds the points any more (build() and set_radius() then never
  /// call a ball whole).
  void add_move(double distance) noexcept {
    if (!(distance <= 0.0)) moved_since_measure_ += distance;
    balls_.add_move(distance);
  }
  /// Points that move, ascending; when global(), every point moves whatever this holds.
  std::span<const std::uint32_t> points() const { return points_; }
  /// The same points in the order the index's queries found them (near one another in space,
  /// with repeats where balls overlap), or points() when that order was not kept. For the
  /// index's list of moved points, which skips its blocks by their bounding boxes: listed in
  /// ascending index order, one block held points from across the region and every query
  /// near it scanned them all (a quarter of a stroke's region frame).
  std::span<const std::uint32_t> points_as_found() const {
    return as_found_complete_ ? std::span<const std::uint32_t>(as_found_) : points();
  }
  /// Whether the last build() tested every point rather than querying the index.
  bool scanned() const { return scanned_; }
  /// The balls answered from candidates kept from an earlier frame, and those queried afresh.
  const BallCache& balls() const { return balls_; }
  /// Points of the pinned band, ascending; a subset of points().
  std::span<const std::uint32_t> border() const { return border_; }
  const RegionSettings& settings() const { return settings_; }
  /// For kRadius regions: a new radius for the next build, not below min_radius() nor above
  /// the radius whose ball, from any point of the model, holds all of it (a budget that would
  /// grow it further has nothing more to give it, and a radius grown without end could not
  /// shrink back from infinity).
  void set_radius(double radius) noexcept;
  double min_radius() const noexcept { return min_radius_; }
  double border_width() const { return border_width_; }

 private:
  // The model's bounding box, measured at construction: every point stays within it, widened
  // on each side by the moves add_move() is told of since. build() and set_radius() judge
  // "holds the model" by it.
  void measure_model(const PointModel& model) noexcept;
  // Distance from c to the farthest point of the box the points can be in, with a margin far
  // above the rounding of the distances the ball queries compare.
  double farthest_point_bound(const Vec3& c) const noexcept;
  // Whether testing each of the model's points against each contact costs less than the ball
  // queries, judged by what the last build's balls found: the queries pay 13-24 ns here for
  // every point they find (the tree's leaves, the union, the band test at scattered
  // positions), a scan about one for every point and contact.
  bool scan_pays(std::size_t model_points, std::size_t contacts) const noexcept;
  // Whether `points` of the model's are past the share that makes the global frame the cheaper
  // (RegionSettings::global_when_cheaper).
  bool past_cheaper_share(std::size_t points, std::size_t model_points) const noexcept {
    return settings_.global_when_cheaper && kRegionPointCost * points > model_points;
  }
  // build()'s points and band once no single ball holds the model: by a scan or by the queries.
  // Returns whether a scan counted past the cheaper share and so listed nothing (scan()).
  [[nodiscard]] bool collect(const PointModel& model, const PointIndex& index, double drift,
                             std::span<const Vec3> contacts, double inner_squared);
  // build() by testing every point: a point is in the region when within the radius of a
  // contact, in the band unless within radius - band of one, by the same comparisons the
  // queries make. After a build that went global for its share, the points are counted first,
  // and it returns true, listing nothing, when the count passes that share.
  [[nodiscard]] bool scan(const PointModel& model, std::span<const Vec3> contacts, double inner_squared) noexcept;

  RegionSettings settings_;
  double border_width_;
  double min_radius_;
  std::vector<std::uint32_t> points_;
  std::vector<std::uint32_t> border_;
  std::vector<std::uint32_t> scratch_;
  std::vector<std::uint32_t> as_found_;  // the queries' results, one after another
  bool as_found_complete_ = false;       // as_found_ holds every point of points_
  bool moves_model_ = false;             // the last build held every point or found the global frame cheaper
  Vec3 box_lo_{}, box_hi_{};             // the model's bounding box when last measured
  Vec3 base_lo_{}, base_hi_{};           // and at construction
  double moved_since_measure_ = 0.0;     // no point moved farther since
  PointSet found_, band_found_;          // empty between frames
  BallCache balls_;                      // the balls' candidates, kept across a stroke's frames
  std::size_t found_last_ = 0;           // points the last build's balls held, once per ball
  bool scanned_ = false;                 // the last build scanned
  bool went_global_for_share_ = false;   // the last build found the global frame the cheaper
};

}  // namespace sculpt::deform
