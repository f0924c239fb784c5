#pragma once
// A model file's normals made fit to use: the readers take normals as the file has them, and a
// zero normal (CGAL's blobby.xyz has nothing else) or a NaN one is a missing normal, while a
// long or short one (OpenCV's parasaurolophus: lengths 0.12 to 6.3) would scale the haptic
// traction by its length. One function decides, so every command that loads a model agrees.

#include <cstddef>
#include <string>

#include "sculpt/deform/point_model.hpp"

namespace sculpt::deform {

/// What to do with a normal that is zero or not finite.
enum class NormalPolicy {
  kReestimate,  ///< treat it as missing and estimate it (reestimate_normals)
  kRefuse,      ///< refuse the model, naming the first such vertex
};

/// A normal whose length is off 1 by more than this is scaled to unit length and counted;
/// closer ones are left bit for bit, so a file written with six digits (or by us) reads back
/// unchanged, and lengths 1 +- 1e-3 change the traction by less than the solver's residual.
inline constexpr double kUnitNormalTolerance = 1e-3;

/// What check_normals() found and did.
struct NormalReport {
  std::size_t zero_or_nonfinite = 0;  ///< normals that were missing in all but name
  std::size_t renormalised = 0;       ///< normals scaled to unit length
};

/// Makes the model's normals unit normals, when it has any (a no-op otherwise):
/// zero (all components exactly 0) or non-finite normals are re-estimated from the points around
/// them and oriented by their nearest good neighbour, or, with kRefuse, refused with a
/// ModelFileError naming `name_for_errors` and the first such vertex, before anything is
/// changed. Only the bad normals are re-estimated: the others came from the scanner or the
/// mesh and carry the file's own orientation, which a fresh estimate of every normal would
/// throw away. A file with no usable normal at all gets all of them estimated (from faces when
/// it has them). Every other normal whose length is off 1 by more than kUnitNormalTolerance is
/// scaled to unit length.
NormalReport check_normals(PointModel& model, NormalPolicy policy, const std::string& name_for_errors);

/// One line for the user: "12 zero or non-finite normals re-estimated, 3,400 normalised", or
/// empty when check_normals() changed nothing.
std::string describe(const NormalReport& report);

}  // namespace sculpt::deform
