#pragma once
// From a fingertip probe to a force: collision detection and force set-up (thesis 4.2.1 and
// 4.3.1, MATH.md §4).

#include <cstdint>
#include <optional>
#include <vector>

#include "sculpt/deform/ball_cache.hpp"
#include "sculpt/deform/point_index.hpp"
#include "sculpt/deform/point_model.hpp"
#include "sculpt/deform/vec3.hpp"

namespace sculpt::deform {

enum class ContactMode {
  kPush,  ///< inward force: the probe starts outside and may never enter
  kPull,  ///< outward force: the probe starts inside and may never leave
};

/// The thesis's offsets, in model units, and how the inside is told from the outside.
/// The largest max_patch_points accepted (a million rows per finger is already far past any
/// frame budget).
inline constexpr std::size_t kMaxPatchPointsLimit = std::size_t{1} << 20;

struct ContactSettings {
  ContactMode mode = ContactMode::kPush;
  double bc_radius = 0.05;            ///< eps: points this close to A follow the probe
  double min_source_distance = 1e-2;  ///< Δd: a source never sits closer than this to A
  double guard_distance = 1e-1;       ///< Δr: a free finger this close constrains its surface
  /// At most this many boundary-condition points per finger's patch: beyond it the patch is
  /// thinned evenly (every k-th point, k = size / cap), its traction resultant scaled by the
  /// points left out. Sizes the frame's buffers at set-up (a dense scan under a wide eps would
  /// otherwise need rows for every point under every finger).
  std::size_t max_patch_points = 1024;
  /// Reference point known to be outside (the scanner); used when the model has no normals.
  std::optional<Vec3> reference;

  /// Throws std::invalid_argument naming the bad setting.
  void validate() const;
};

/// The accepted positions of one probe, oldest first. `previous` is the position before
/// `current`; `earlier` the one before that, when known.
struct ProbeMotion {
  Vec3 previous;
  Vec3 current;
  std::optional<Vec3> earlier;
};

/// Where a probe stands against the pseudo-surface. Each side is a signed distance along the
/// outside direction, negative inside.
struct SurfaceSide {
  std::uint32_t nearest = PointIndex::kNoPoint;  ///< A, the nearest model point
  double distance = 0.0;                         ///< |P - A|
  /// The thesis's one-point test (4.2.1.1-2): n_A . (P - A) with normals,
  /// (P - A) . (R - A)/|R - A| with a reference point.
  double plane_side = 0.0;
  /// The surface of the points around the probe, through A (see locate()); plane_side where it
  /// is not evaluated.
  double surface_side = 0.0;
  /// What collision detection reads: min(plane_side, surface_side) for a push, the max for a
  /// pull (see locate()).
  double side = 0.0;
};

/// The smoothing length h of locate()'s surface: the finger's radius eps, shrunk on a model so
/// dense that an eps-ball holds more than about 24 points (the median over an even sample), so
/// that a query's cost stays bounded whatever eps is. Set-up work: allocates.
double side_smoothing(const PointModel& model, const PointIndex& index, double bc_radius);

/// Nearest point A and side of `probe`, exact for a model that moved at most `drift` since the
/// index was built. The model must have normals or settings.reference must be set.
///
/// A's plane alone (the thesis) reads one carried normal, and in a crease the finger itself made
/// that normal can tilt the wrong way: a finger under the crease's wall then reads as outside
/// and passes through. So within 2h of the model (h = `smoothing`) the side also reads the
/// surface of the points around the probe, an implicit moving-least-squares surface
/// f(q) = sum w_i o_i . (q - p_i) / sum w_i, with o_i each point's outside direction and
/// w_i = (1 - t_i)^2 for t_i = (|q - p_i|^2 - |q - A|^2) / (4 h^2) < 1, measured against its value
/// at A: surface_side = f(P) - f(A). It is 0 on a model point as the thesis's side is, the exact
/// distance to a flat patch's plane, and it passes through the samples rather than off them by
/// the curvature. The probe is across when either estimate says so: side = min(plane_side,
/// surface_side) for a push (a finger both see outside is free), the max for a pull. Farther
/// than 2h, and when the neighbourhood does not fit in `neighbours`, side = plane_side.
/// `neighbours` is scratch: reserve() it for the model's size; it is never grown. `hint` is a
/// guess at A that speeds the search (PointIndex::nearest); the result does not depend on it.
/// `balls`, when given, answers both queries from the probe's balls kept across frames
/// (BallCache, ascending; its moves told by the caller), to the same points and order as the
/// index, so the result does not depend on it either. Does not allocate or throw.
SurfaceSide locate(const PointModel& model, const PointIndex& index, double drift, const Vec3& probe,
                   const ContactSettings& settings, double smoothing, std::vector<std::uint32_t>& neighbours,
                   std::uint32_t hint = PointIndex::kNoPoint, BallCache* balls = nullptr) noexcept;

/// The same with its own scratch and smoothing (side_smoothing()): allocates; for set-up and
/// tests, never the tick.
SurfaceSide locate(const PointModel& model, const PointIndex& index, double drift, const Vec3& probe,
                   const ContactSettings& settings);

/// True when a probe at `side` has crossed the surface the way `mode` forbids: inside for a
/// push, outside for a pull. Grazing (side == 0) is no collision.
inline bool crossed(ContactMode mode, double side) { return mode == ContactMode::kPush ? side < 0.0 : side > 0.0; }

/// How the source point was chosen (the Δd rule).
enum class SourceRule {
  kPrevious,    ///< the last probe position before the collision
  kEarlier,     ///< the one before it, because the previous was closer than Δd to A
  kPushedBack,  ///< no usable earlier position: moved back from A along -F to distance Δd
  kCleared,     ///< the chosen point was too close to a model point: moved back along -F or A's normal
};

struct ForceSetup {
  Vec3 source;
  Vec3 force;  ///< F = P_f - A
  SourceRule rule = SourceRule::kPrevious;
};

/// F = P_f - A and its source (MATH.md §4): the previous probe position, or the earlier one
/// when the previous is closer than Δd to A; with neither usable, the point at distance Δd
/// from A along -F (away from where the probe went), so the kernel is never near-singular.
ForceSetup set_up_force(const ProbeMotion& motion, const Vec3& contact, double min_source_distance);

}  // namespace sculpt::deform
