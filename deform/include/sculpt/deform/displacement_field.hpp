#pragma once
// The hot loop: adds the superposed displacement of a few point forces to many points.

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "sculpt/deform/field_worker.hpp"
#include "sculpt/deform/kernel.hpp"
#include "sculpt/deform/point_model.hpp"

namespace sculpt::deform {

/// Two hands of five fingers: the most sources one frame can hold. Fixed so that the hot loop
/// and the solver keep their working arrays on the stack.
inline constexpr std::size_t kMaxSources = 10;

/// A point force: where it acts and its effective force (what is logged and what the traction
/// uses).
struct SourceForce {
  Vec3 source;
  Vec3 force;
};

/// The arithmetic precision of the per-point loop. Positions are stored as float either way;
/// kDouble evaluates the kernel and the normal update in double and rounds once at the store.
enum class Precision { kFloat, kDouble };

struct FieldOptions {
  Precision precision = Precision::kFloat;
  /// Carry normals with the deformation gradient, n' = normalize(F^-T n) (MATH.md §6). Ignored
  /// when the model has no normals.
  bool carry_normals = true;
  /// The bounded normal update, a named approximation (0, the default: off). Where the sum over
  /// the sources of a bound on ||grad u||_2 at a point is at most this, the gradient may be left
  /// out (it is, unless most of the points computed with it need theirs): the point keeps its
  /// normal, which is then within asin(b / (1 - b)) of the carried one, and
  /// det(I + grad u) >= (1 - b)^3 > 0 there, so no fold is hidden from the guard (the README's
  /// physics notes derive both). Every other normal and Jacobian is exactly the exact pass's, bit
  /// for bit; positions always are. FieldResult counts the normals kept. In [0, 0.1].
  double normal_skip_bound = 0.0;
  /// A named approximation (off by default): in float precision, 1/r of every point and source
  /// comes from the processor's reciprocal square root estimate refined by one Newton step
  /// (inverse_sqrt_estimate(), relative error at most kInverseSqrtEstimateError = 2^-21) in place
  /// of a square root and a division. Displacements, gradients and normals all use it, so every
  /// pass still agrees with the others bit for bit; thread counts too. Ignored in double precision.
  bool fast_inverse_sqrt = false;
};

/// The positions and normals a frame overwrote, so that a frame rejected after it ran (a fold,
/// a non-finite value) can be undone bit for bit. Sized at set-up for the most points one frame
/// may move; recording and restoring never allocate.
class UndoJournal {
 public:
  /// Room for `points` moved points (with their normals when `normals`). Allocates.
  void reserve(std::size_t points, bool normals);
  std::size_t capacity() const { return index_.size(); }
  std::size_t size() const { return count_; }
  void clear() noexcept { count_ = 0; }
  /// Writes the recorded values back. No allocation.
  void restore(PointModel& model) const noexcept;

 private:
  friend struct JournalWriter;
  // Sized once by reserve(); count_ of them are in use. One array per attribute, so a block of
  // points is recorded with straight copies.
  std::vector<std::uint32_t> index_;
  std::vector<float> x_, y_, z_, nx_, ny_, nz_;
  std::size_t count_ = 0;
  bool normals_ = false;
  bool contiguous_ = false;        // the recorded points are 0 .. count_ - 1: index_ is not written
  bool recorded_normals_ = false;  // the last pass carried normals, so they are in nx_ .. nz_
};

/// The largest FieldOptions::normal_skip_bound: a kept normal then stays within 0.11 rad.
inline constexpr double kMaxNormalSkipBound = 0.1;

/// The bound on the angle between a kept normal and the carried one, asin(b / (1 - b)), for a
/// gradient bound b <= kMaxNormalSkipBound (0 for b = 0).
double normal_bound_angle(double gradient_bound) noexcept;

/// What a pass of the displacement loop did.
struct FieldResult {
  double max_displacement = 0.0;  ///< largest displacement length applied
  /// Smallest det(I + grad u) over the moved points (MATH.md §6): <= 0 means the frame folded
  /// the material there. 1 when nothing moved or the Jacobian was not asked for.
  double min_jacobian = 1.0;
  /// False when a displacement, a new position, a carried normal or a Jacobian was not finite
  /// (the model then holds those values until the caller restores the journal).
  bool finite = true;
  /// With FieldOptions::normal_skip_bound: the moved points whose gradient was bounded, not
  /// computed, and the largest bound among them (0 when none was skipped).
  std::size_t gradients_skipped = 0;
  double max_skipped_bound = 0.0;
};

/// Moves the points `indices` (ascending, unique) of `model` by the displacement of `sources`,
/// evaluated at their positions before the move, and carries their normals along. With
/// `indices` empty and `all_points` true, every point moves (contiguous, fastest). With
/// `jacobian`, det(I + grad u) is evaluated at every moved point even when no normal is carried.
/// With `journal` (cleared first, reserved for every moved point) the old values are recorded
/// so the caller can undo the pass. With `worker`, a large pass is split between the caller and
/// the worker's core; the result is bit for bit the same. No allocation; noexcept; at most
/// kMaxSources sources.
FieldResult apply_displacements(PointModel& model, const Kernel& kernel, std::span<const SourceForce> sources,
                                std::span<const std::uint32_t> indices, bool all_points, const FieldOptions& options,
                                bool jacobian = false, UndoJournal* journal = nullptr,
                                FieldWorker* worker = nullptr) noexcept;

}  // namespace sculpt::deform
