#pragma once
// One view of one model: an offscreen OpenGL context (Mesa's OSMesa, software rasterised by
// llvmpipe), Lambert shading, depth-tested faces or splats, and an overlay on top.

#include <memory>
#include <stdexcept>

#include "sculpt/render/camera.hpp"
#include "sculpt/render/image.hpp"
#include "sculpt/render/lighting.hpp"
#include "sculpt/render/overlay.hpp"
#include "sculpt/render/render_model.hpp"

namespace sculpt::render {

class OffscreenContext;

/// Thrown when no OpenGL context can be made (OSMesa missing or out of memory).
class RenderError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class ViewRenderer {
 public:
  /// `supersample` x `supersample` samples per output pixel (box filtered): OSMesa has no
  /// multisampling, and edges of splats and arrows alias badly without it.
  /// Throws std::invalid_argument for a size outside [1, 8192] or supersample outside [1, 4], and
  /// RenderError when the context cannot be made.
  ViewRenderer(int width, int height, int supersample = 2);
  ~ViewRenderer();
  ViewRenderer(const ViewRenderer&) = delete;
  ViewRenderer& operator=(const ViewRenderer&) = delete;

  int width() const { return width_; }
  int height() const { return height_; }

  /// Draws `model` (then `overlay`) as `camera` sees it; the camera's size must be this
  /// renderer's (throws std::invalid_argument otherwise).
  Image render(const RenderModel& model, const Camera& camera, const Lighting& lighting = {},
               const Overlay& overlay = {});

 private:
  int width_ = 0;
  int height_ = 0;
  int supersample_ = 1;
  std::unique_ptr<OffscreenContext> context_;
};

}  // namespace sculpt::render
