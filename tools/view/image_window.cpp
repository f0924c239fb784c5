#include "image_window.hpp"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#define GLFW_EXPOSE_NATIVE_X11
#include <GLFW/glfw3native.h>
#include <X11/Xlib.h>
#include <X11/Xutil.h>

#include <bit>
#include <cstdint>
#include <cstring>

namespace sculpt::view {
namespace {

// Where a colour channel sits in a pixel of the window's visual, from its mask.
struct Channel {
  unsigned long mask = 0;
  int shift = 0;
  int bits = 0;
};

Channel channel(unsigned long mask) { return {mask, mask ? std::countr_zero(mask) : 0, std::popcount(mask)}; }

unsigned long pack(const Channel& c, std::uint8_t value) {
  return (static_cast<unsigned long>(value) >> (8 - c.bits) << c.shift) & c.mask;
}

std::uint8_t unpack(const Channel& c, unsigned long pixel) {
  const unsigned long v = (pixel & c.mask) >> c.shift;
  return static_cast<std::uint8_t>(c.bits >= 8 ? v >> (c.bits - 8) : v << (8 - c.bits));
}

}  // namespace

struct WindowInput {
  std::vector<Key> keys;
  PointerMotion pointer;
  bool dragging = false;
  bool cursor_known = false;
  double x = 0.0, y = 0.0;  // the cursor as its last motion event put it
};

namespace {

WindowInput& input_of(GLFWwindow* window) { return *static_cast<WindowInput*>(glfwGetWindowUserPointer(window)); }

void on_key(GLFWwindow* window, int key, int, int action, int) {
  if (action != GLFW_PRESS && action != GLFW_REPEAT) return;
  std::vector<Key>& keys = input_of(window).keys;
  switch (key) {
    case GLFW_KEY_SPACE: keys.push_back(Key::kPause); break;
    case GLFW_KEY_N:
    case GLFW_KEY_RIGHT: keys.push_back(Key::kStep); break;
    case GLFW_KEY_Q:
    case GLFW_KEY_ESCAPE: keys.push_back(Key::kQuit); break;
    case GLFW_KEY_KP_ADD: keys.push_back(Key::kFaster); break;
    case GLFW_KEY_KP_SUBTRACT: keys.push_back(Key::kSlower); break;
    case GLFW_KEY_A: keys.push_back(Key::kOrbitLeft); break;
    case GLFW_KEY_D: keys.push_back(Key::kOrbitRight); break;
    case GLFW_KEY_W: keys.push_back(Key::kTiltUp); break;
    case GLFW_KEY_S: keys.push_back(Key::kTiltDown); break;
    case GLFW_KEY_Z: keys.push_back(Key::kCloser); break;
    case GLFW_KEY_X: keys.push_back(Key::kFarther); break;
    case GLFW_KEY_R: keys.push_back(Key::kResetView); break;
    default: break;
  }
}

// '+' and '-' by the character they type, whatever the keyboard layout puts them on.
void on_char(GLFWwindow* window, unsigned int codepoint) {
  std::vector<Key>& keys = input_of(window).keys;
  if (codepoint == '+') keys.push_back(Key::kFaster);
  if (codepoint == '-') keys.push_back(Key::kSlower);
}

// A drag starts where the left button goes down and adds each move of the cursor while it is
// held (X grabs the pointer meanwhile, so a drag may leave the window and still count). Where
// it went down is where the motion events had put the cursor: a poll handles the events that
// queued since the last, and asking the server instead would give where the cursor is now,
// after the moves still queued behind the press.
void on_button(GLFWwindow* window, int button, int action, int) {
  if (button != GLFW_MOUSE_BUTTON_LEFT) return;
  WindowInput& in = input_of(window);
  in.dragging = action == GLFW_PRESS;
  if (in.dragging && !in.cursor_known) {
    glfwGetCursorPos(window, &in.x, &in.y);  // no motion seen yet: the best there is
    in.cursor_known = true;
  }
}

void on_cursor(GLFWwindow* window, double x, double y) {
  WindowInput& in = input_of(window);
  if (in.dragging) {
    in.pointer.drag_x += x - in.x;
    in.pointer.drag_y += y - in.y;
  }
  in.x = x;
  in.y = y;
  in.cursor_known = true;
}

void on_scroll(GLFWwindow* window, double, double notches) { input_of(window).pointer.scroll += notches; }

}  // namespace

struct ImageWindow::Native {
  Display* display = nullptr;
  Window window = 0;
  GC gc = nullptr;
  Visual* visual = nullptr;
  int depth = 0;
  Channel red, green, blue;
  std::vector<std::uint32_t> pixels;
};

ImageWindow::ImageWindow(int width, int height, const std::string& title) : width_(width), height_(height) {
  if (!glfwInit()) throw WindowError("cannot open a window: no X display (is DISPLAY set?)");
  glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);  // the pictures come from OSMesa, not from GLX
  glfwWindowHint(GLFW_RESIZABLE, GLFW_FALSE);
  window_ = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
  if (window_ == nullptr) {
    glfwTerminate();
    throw WindowError("cannot open a window: GLFW could not create it");
  }
  input_ = std::make_unique<WindowInput>();
  glfwSetWindowUserPointer(window_, input_.get());
  glfwSetKeyCallback(window_, on_key);
  glfwSetCharCallback(window_, on_char);
  glfwSetMouseButtonCallback(window_, on_button);
  glfwSetCursorPosCallback(window_, on_cursor);
  glfwSetScrollCallback(window_, on_scroll);
  native_ = new Native;
  native_->display = glfwGetX11Display();
  native_->window = glfwGetX11Window(window_);
  XWindowAttributes attributes{};
  XGetWindowAttributes(native_->display, native_->window, &attributes);
  native_->visual = attributes.visual;
  native_->depth = attributes.depth;
  native_->red = channel(attributes.visual->red_mask);
  native_->green = channel(attributes.visual->green_mask);
  native_->blue = channel(attributes.visual->blue_mask);
  native_->gc = XCreateGC(native_->display, native_->window, 0, nullptr);
  native_->pixels.resize(static_cast<std::size_t>(width) * height);
}

ImageWindow::~ImageWindow() {
  if (native_ != nullptr) {
    XFreeGC(native_->display, native_->gc);
    delete native_;
  }
  glfwDestroyWindow(window_);
  glfwTerminate();
}

void ImageWindow::show(const render::Image& image) {
  if (image.width != width_ || image.height != height_) return;
  Native& n = *native_;
  for (int y = 0; y < height_; ++y) {
    for (int x = 0; x < width_; ++x) {
      const std::uint8_t* p = image.at(x, y);
      n.pixels[static_cast<std::size_t>(y) * width_ + x] =
          static_cast<std::uint32_t>(pack(n.red, p[0]) | pack(n.green, p[1]) | pack(n.blue, p[2]));
    }
  }
  XImage* ximage = XCreateImage(n.display, n.visual, static_cast<unsigned>(n.depth), ZPixmap, 0,
                                reinterpret_cast<char*>(n.pixels.data()), static_cast<unsigned>(width_),
                                static_cast<unsigned>(height_), 32, width_ * 4);
  if (ximage == nullptr) return;
  XPutImage(n.display, n.window, n.gc, ximage, 0, 0, 0, 0, static_cast<unsigned>(width_),
            static_cast<unsigned>(height_));
  ximage->data = nullptr;  // ours, not Xlib's to free
  XDestroyImage(ximage);
  XFlush(n.display);
}

render::Image ImageWindow::capture() const {
  const Native& n = *native_;
  XSync(n.display, False);
  render::Image image(width_, height_, {});
  XImage* ximage = XGetImage(n.display, n.window, 0, 0, static_cast<unsigned>(width_), static_cast<unsigned>(height_),
                             AllPlanes, ZPixmap);
  if (ximage == nullptr) return image;
  for (int y = 0; y < height_; ++y) {
    for (int x = 0; x < width_; ++x) {
      const unsigned long pixel = XGetPixel(ximage, x, y);
      std::uint8_t* p = image.at(x, y);
      p[0] = unpack(n.red, pixel);
      p[1] = unpack(n.green, pixel);
      p[2] = unpack(n.blue, pixel);
    }
  }
  XDestroyImage(ximage);
  return image;
}

std::vector<Key> ImageWindow::poll() {
  glfwPollEvents();
  std::vector<Key> keys;
  keys.swap(input_->keys);
  return keys;
}

PointerMotion ImageWindow::take_pointer() {
  const PointerMotion motion = input_->pointer;
  input_->pointer = {};
  return motion;
}

bool ImageWindow::closed() const { return glfwWindowShouldClose(window_) != 0; }

}  // namespace sculpt::view
