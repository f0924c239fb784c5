#pragma once
// A window that shows pictures rendered elsewhere. The pictures come from OSMesa, and libOSMesa
// exports every gl* entry point itself, so this process must not also load GLX's libGL: the
// window is made by GLFW with no client API (no OpenGL context at all) and each picture is
// copied into it with Xlib's XPutImage.

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "sculpt/render/image.hpp"

struct GLFWwindow;

namespace sculpt::view {

/// No display to open a window on (DISPLAY unset, no X server), or GLFW failed.
class WindowError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The keys the viewer acts on.
enum class Key {
  kPause,
  kStep,
  kFaster,
  kSlower,
  kQuit,
  kOrbitLeft,
  kOrbitRight,
  kTiltUp,
  kTiltDown,
  kCloser,
  kFarther,
  kResetView
};

/// What the mouse did since the last poll: a left-button drag in pixels (right and down
/// positive), and wheel notches (away from the user positive).
struct PointerMotion {
  double drag_x = 0.0;
  double drag_y = 0.0;
  double scroll = 0.0;
};

struct WindowInput;  // image_window.cpp's

class ImageWindow {
 public:
  /// Opens a `width` x `height` window titled `title`. @throw WindowError
  ImageWindow(int width, int height, const std::string& title);
  ~ImageWindow();
  ImageWindow(const ImageWindow&) = delete;
  ImageWindow& operator=(const ImageWindow&) = delete;

  /// Copies `image` (the window's size) into the window.
  void show(const render::Image& image);
  /// What the X server shows in the window now (XGetImage).
  render::Image capture() const;
  /// Handles window events; the keys pressed since the last call, in order.
  std::vector<Key> poll();
  /// The mouse's motion gathered by the polls since the last call.
  PointerMotion take_pointer();
  /// The window was closed by its window manager.
  bool closed() const;

 private:
  struct Native;
  GLFWwindow* window_ = nullptr;
  Native* native_ = nullptr;
  std::unique_ptr<WindowInput> input_;  // what GLFW's callbacks gather between polls
  int width_ = 0;
  int height_ = 0;
};

}  // namespace sculpt::view
