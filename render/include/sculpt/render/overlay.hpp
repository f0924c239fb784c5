#pragma once
// What is drawn over a model: markers (probe positions), polylines (fingertip paths) and
// arrows (forces), all in model coordinates. Overlays are drawn after the model without the
// depth test, so a probe pressed into the surface stays visible.

#include <vector>

#include "sculpt/render/camera.hpp"
#include "sculpt/render/image.hpp"

namespace sculpt::render {

struct Marker {
  Vec3 position;
  Rgb color;
  double diameter_px = 8.0;  ///< in output pixels, whatever the distance
};

struct Polyline {
  std::vector<Vec3> points;
  Rgb color;
};

struct Arrow {
  Vec3 from;
  Vec3 to;  ///< the head
  Rgb color;
};

struct Overlay {
  std::vector<Polyline> paths;
  std::vector<Arrow> arrows;
  std::vector<Marker> markers;

  bool empty() const { return paths.empty() && arrows.empty() && markers.empty(); }
};

}  // namespace sculpt::render
