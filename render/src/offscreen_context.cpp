#include "offscreen_context.hpp"

#include <GL/osmesa.h>

#include <string>

#include "sculpt/render/view_renderer.hpp"

namespace sculpt::render {

OffscreenContext::OffscreenContext(int width, int height)
    : width_(width), height_(height), buffer_(static_cast<std::size_t>(width) * height * 4) {
  context_ = OSMesaCreateContextExt(OSMESA_RGBA, 24, 0, 0, nullptr);
  if (context_ == nullptr) {
    throw RenderError("OSMesa could not create an OpenGL context (is Mesa's libOSMesa installed?)");
  }
}

OffscreenContext::~OffscreenContext() { OSMesaDestroyContext(context_); }

void OffscreenContext::make_current() {
  if (!OSMesaMakeCurrent(context_, buffer_.data(), GL_UNSIGNED_BYTE, width_, height_)) {
    throw RenderError("OSMesa could not bind a " + std::to_string(width_) + "x" + std::to_string(height_) +
                      " drawing buffer");
  }
}

}  // namespace sculpt::render

#if defined(__SANITIZE_ADDRESS__)
// LeakSanitizer's suppressions for every program that draws through this file. OSMesa keeps
// each framebuffer it makes in OSMesaMakeCurrent on a global list, for reuse, and its API has
// no call that frees them: about 260 bytes a context, 480 in a one-picture run, which
// LeakSanitizer reports at exit and fails the run with. Only allocations made inside
// libOSMesa are passed over; ours (the contexts' owners, the pixel buffers) are still checked.
// Defined here, beside the only code that calls OSMesa, so the sculpt binary and render_tests
// need no environment for it.
extern "C" const char* __lsan_default_suppressions() { return "leak:libOSMesa.so\n"; }
#endif
