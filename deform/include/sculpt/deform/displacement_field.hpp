#pragma once
// The hot loop: adds the superposed displacement of a few point forces to many points.

#include <cstddef>
#include <cstdint>
#include <span>

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
};

/// Moves the points `indices` (ascending, unique) of `model` by the displacement of `sources`,
/// evaluated at their positions before the move, and carries their normals along. With
/// `indices` empty and `all_points` true, every point moves (contiguous, fastest). Returns the
/// largest displacement length applied. No allocation; noexcept; at most kMaxSources sources.
double apply_displacements(PointModel& model, const Kernel& kernel,
                           std::span<const SourceForce> sources,
                           std::span<const std::uint32_t> indices, bool all_points,
                           const FieldOptions& options) noexcept;

}  // namespace sculpt::deform
