#pragma once
// An OpenGL context that draws into memory: Mesa's OSMesa, rasterised on the CPU by llvmpipe,
// so pictures can be made on machines with neither a display nor a GPU.

#include <cstdint>
#include <vector>

struct osmesa_context;  // OSMesaContext, without pulling <GL/osmesa.h> into every includer

namespace sculpt::render {

class OffscreenContext {
 public:
  /// A legacy (compatibility) context with a 24-bit depth buffer drawing into a width x height
  /// RGBA buffer. Throws RenderError when Mesa cannot make one.
  OffscreenContext(int width, int height);
  ~OffscreenContext();
  OffscreenContext(const OffscreenContext&) = delete;
  OffscreenContext& operator=(const OffscreenContext&) = delete;

  /// Binds the context and its buffer to the calling thread; throws RenderError on failure.
  void make_current();
  int width() const { return width_; }
  int height() const { return height_; }
  /// RGBA bytes, bottom row first (OpenGL's convention); complete after glFinish().
  const std::uint8_t* pixels() const { return buffer_.data(); }

 private:
  osmesa_context* context_ = nullptr;
  int width_ = 0;
  int height_ = 0;
  std::vector<std::uint8_t> buffer_;
};

}  // namespace sculpt::render
