#pragma once
// Consistent winding of a mesh's triangles. An export may mix windings (the snowden bust has 12
// of its 109,259 faces wound against their neighbours), and every normal computed from such
// faces points inward where its face is wound backwards: the deformer then classes a press from
// outside as coming from inside.

#include <cstddef>

#include "sculpt/deform/point_model.hpp"

namespace sculpt::deform {

struct FaceOrientation {
  std::size_t turned = 0;      ///< triangles whose winding was reversed
  std::size_t components = 0;  ///< edge-connected pieces of the mesh
  /// Shared edges across which no consistent winding exists (a Möbius band) or that more than
  /// two triangles share: left as they are, and not crossed when propagating.
  std::size_t conflicts = 0;
};

/// Rewinds model.triangles so that two triangles sharing an edge traverse it in opposite
/// directions (the winding of an orientable surface). Of each edge-connected piece's two
/// consistent windings, the one most of its faces already have is kept, so only the faces that
/// disagree with their neighbours turn: the file says which side is out (a hollow shell's cavity
/// wall rightly faces into the cavity). Positions and normals are untouched.
/// Throws std::invalid_argument when the index count is not a multiple of 3 or an index is out
/// of range. Set-up time: allocates.
FaceOrientation orient_faces(PointModel& model);

}  // namespace sculpt::deform
