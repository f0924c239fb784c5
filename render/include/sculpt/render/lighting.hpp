#pragma once
// Lambert shading: one directional key light fixed to the camera, computed per point on the
// CPU (not by OpenGL's fixed-function lighting, which lights points from one side only and
// cannot flip a normal that a scan's orientation got wrong).

#include <vector>

#include "sculpt/render/camera.hpp"
#include "sculpt/render/image.hpp"
#include "sculpt/render/render_model.hpp"

namespace sculpt::render {

/// The light and the background. The light is fixed to the camera (x right, y up, z toward
/// the viewer), so every view of a model is lit alike: from the upper left, a little in front.
struct Lighting {
  Vec3 light_in_camera{-0.45, 0.55, 0.70};  ///< toward the light; normalised when used
  double ambient = 0.28;                    ///< what a point facing away from the light keeps
  double diffuse = 0.72;                    ///< added, times max(0, n . l)
  Rgb background{0.94, 0.95, 0.97};
};

/// The light's direction in world coordinates for `camera`: light_in_camera turned by the
/// camera's basis, normalised.
Vec3 light_direction(const Camera& camera, const Lighting& lighting);

/// Each point's base colour times (ambient + diffuse * max(0, n . l)), r, g, b per point, with
/// every normal first turned toward the eye: the side of the surface the camera sees is lit
/// whatever the orientation of the normals (unoriented PCA normals, flipped faces).
void shade(const RenderModel& model, const Camera& camera, const Lighting& lighting, std::vector<float>& colors);

}  // namespace sculpt::render
