#include "sculpt/render/view_renderer.hpp"

#define GL_GLEXT_PROTOTYPES 1  // glPointParameterfv is OpenGL 1.4, declared in glext.h
#include <GL/gl.h>
#include <GL/glext.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "offscreen_context.hpp"

namespace sculpt::render {
namespace {

// Largest view edge accepted: well inside what llvmpipe rasterises (16384) after supersampling.
constexpr int kMaxEdge = 8192;
constexpr float kOverlayLinePx = 2.0f;
constexpr double kArrowHeadPx = 14.0;
constexpr double kMarkerOutlinePx = 3.0;

void color(const Rgb& c) { glColor3d(c.r, c.g, c.b); }
void vertex(const Vec3& p) { glVertex3d(p.x, p.y, p.z); }

// Round splats of one world-space size: the base size is divided by the eye distance
// (attenuation 0 + 0 d + 1 d^2 under a square root), which is what perspective does to a disc.
void draw_splats(const RenderModel& model, const Camera& camera, int supersample) {
  glEnable(GL_POINT_SMOOTH);
  // Smooth points put their round coverage in alpha; the alpha test keeps the inside of the disc
  // opaque and depth-tested instead of blending it.
  glEnable(GL_ALPHA_TEST);
  glAlphaFunc(GL_GREATER, 0.5f);
  const GLfloat attenuation[3] = {0.0f, 0.0f, 1.0f};
  glPointParameterfv(GL_POINT_DISTANCE_ATTENUATION, attenuation);
  for (const SplatClass& splats : model.splat_classes()) {
    glPointSize(static_cast<GLfloat>(splats.diameter * camera.focal_pixels() * supersample));
    glDrawElements(GL_POINTS, static_cast<GLsizei>(splats.points.size()), GL_UNSIGNED_INT, splats.points.data());
  }
  const GLfloat none[3] = {1.0f, 0.0f, 0.0f};
  glPointParameterfv(GL_POINT_DISTANCE_ATTENUATION, none);
}

void draw_markers(const std::vector<Marker>& markers, int supersample) {
  glEnable(GL_POINT_SMOOTH);
  glEnable(GL_ALPHA_TEST);
  glAlphaFunc(GL_GREATER, 0.5f);
  for (const Marker& m : markers) {
    // A dark ring first, so a marker reads on light and dark surfaces alike.
    glPointSize(static_cast<GLfloat>((m.diameter_px + kMarkerOutlinePx) * supersample));
    glBegin(GL_POINTS);
    glColor3d(0.1, 0.1, 0.1);
    vertex(m.position);
    glEnd();
    glPointSize(static_cast<GLfloat>(m.diameter_px * supersample));
    glBegin(GL_POINTS);
    color(m.color);
    vertex(m.position);
    glEnd();
  }
}

// An arrow's head is a triangle facing the camera, kArrowHeadPx long on screen however far the
// arrow is, and never longer than the arrow itself.
void draw_arrow(const Arrow& a, const Camera& camera) {
  const Vec3 along = a.to - a.from;
  const double length = norm(along);
  if (!(length > 0.0)) return;
  const Vec3 dir = along * (1.0 / length);
  Vec3 right, up, back;
  camera.basis(right, up, back);
  const double depth = std::max(dot(camera.eye - a.to, back), camera.near_distance);
  const double head = std::min(length, kArrowHeadPx * depth / camera.focal_pixels());
  Vec3 side = cross(dir, back);
  side = squared_norm(side) > 0.0 ? normalized(side) : right;
  const Vec3 base = a.to - head * dir;
  color(a.color);
  glBegin(GL_LINES);
  vertex(a.from);
  vertex(base);
  glEnd();
  glBegin(GL_TRIANGLES);
  vertex(a.to);
  vertex(base + 0.4 * head * side);
  vertex(base - 0.4 * head * side);
  glEnd();
}

void draw_overlay(const Overlay& overlay, const Camera& camera, int supersample) {
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_POINT_SMOOTH);
  glDisable(GL_ALPHA_TEST);
  glLineWidth(kOverlayLinePx * supersample);
  for (const Polyline& path : overlay.paths) {
    color(path.color);
    glBegin(GL_LINE_STRIP);
    for (const Vec3& p : path.points) vertex(p);
    glEnd();
  }
  for (const Arrow& a : overlay.arrows) draw_arrow(a, camera);
  draw_markers(overlay.markers, supersample);
}

// The supersampled RGBA buffer (bottom row first) averaged down to the output picture.
Image downsample(const OffscreenContext& context, int width, int height, int s) {
  Image image(width, height, Rgb{});
  const std::uint8_t* rgba = context.pixels();
  const int stride = context.width() * 4;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      unsigned sum[3] = {0, 0, 0};
      for (int dy = 0; dy < s; ++dy) {
        const int row = context.height() - 1 - (y * s + dy);
        for (int dx = 0; dx < s; ++dx) {
          const std::uint8_t* p = rgba + row * stride + (x * s + dx) * 4;
          for (int c = 0; c < 3; ++c) sum[c] += p[c];
        }
      }
      std::uint8_t* out = image.at(x, y);
      const unsigned n = static_cast<unsigned>(s * s);
      for (int c = 0; c < 3; ++c) out[c] = static_cast<std::uint8_t>((sum[c] + n / 2) / n);
    }
  }
  return image;
}

}  // namespace

ViewRenderer::ViewRenderer(int width, int height, int supersample)
    : width_(width), height_(height), supersample_(supersample) {
  if (width < 1 || height < 1 || width > kMaxEdge || height > kMaxEdge) {
    throw std::invalid_argument("view size " + std::to_string(width) + "x" + std::to_string(height) +
                                " is outside 1x1 to " + std::to_string(kMaxEdge) + "x" + std::to_string(kMaxEdge));
  }
  if (supersample < 1 || supersample > 4) throw std::invalid_argument("supersample must be 1 to 4");
  context_ = std::make_unique<OffscreenContext>(width * supersample, height * supersample);
}

ViewRenderer::~ViewRenderer() = default;

Image ViewRenderer::render(const RenderModel& model, const Camera& camera, const Lighting& lighting,
                           const Overlay& overlay) {
  if (camera.width != width_ || camera.height != height_) {
    throw std::invalid_argument("the camera is for a " + std::to_string(camera.width) + "x" +
                                std::to_string(camera.height) + " picture, the renderer draws " +
                                std::to_string(width_) + "x" + std::to_string(height_));
  }
  context_->make_current();
  glViewport(0, 0, context_->width(), context_->height());
  glClearColor(static_cast<GLfloat>(lighting.background.r), static_cast<GLfloat>(lighting.background.g),
               static_cast<GLfloat>(lighting.background.b), 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glDisable(GL_LIGHTING);  // shaded per point on the CPU (lighting.hpp)
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glMatrixMode(GL_PROJECTION);
  glLoadMatrixd(camera.projection_matrix().data());
  glMatrixMode(GL_MODELVIEW);
  glLoadMatrixd(camera.view_matrix().data());

  std::vector<float> shaded;
  shade(model, camera, lighting, shaded);
  glEnableClientState(GL_VERTEX_ARRAY);
  glEnableClientState(GL_COLOR_ARRAY);
  glVertexPointer(3, GL_FLOAT, 0, model.positions().data());
  glColorPointer(3, GL_FLOAT, 0, shaded.data());
  if (model.has_faces()) {
    glShadeModel(GL_SMOOTH);
    glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(model.triangles().size()), GL_UNSIGNED_INT,
                   model.triangles().data());
  } else {
    draw_splats(model, camera, supersample_);
  }
  glDisableClientState(GL_COLOR_ARRAY);
  glDisableClientState(GL_VERTEX_ARRAY);

  if (!overlay.empty()) draw_overlay(overlay, camera, supersample_);
  glFinish();
  return downsample(*context_, width_, height_, supersample_);
}

}  // namespace sculpt::render
