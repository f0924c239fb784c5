#include "sculpt/render/picture.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "sculpt/render/color_bar.hpp"
#include "sculpt/render/heat_map.hpp"
#include "sculpt/render/render_model.hpp"
#include "sculpt/render/text.hpp"

namespace sculpt::render {
namespace {

constexpr int kMaxViews = 36;
constexpr Rgb kLabelInk{0.15, 0.15, 0.18};
constexpr double kMargin = 1.15;  // the model fills 1 / kMargin of the view's limiting side

// `v` turned by `degrees` about the unit axis `k` (Rodrigues' formula).
Vec3 turn(const Vec3& v, const Vec3& k, double degrees) {
  const double a = degrees * std::numbers::pi / 180.0;
  return std::cos(a) * v + std::sin(a) * cross(k, v) + (1.0 - std::cos(a)) * dot(k, v) * k;
}

// Every position the views must show: the models and the overlay (a probe's path starts
// outside the model).
struct Framing {
  Vec3 centre;
  double radius = 0.0;
  std::vector<Vec3> points;  // to tighten each view's camera on
};

Framing frame(const deform::PointModel& model, const deform::PointModel* before, const Overlay& overlay) {
  Bounds box = bounds_of(model);
  if (before != nullptr) box.add(bounds_of(*before));
  std::vector<Vec3> extra;
  for (const Polyline& p : overlay.paths) extra.insert(extra.end(), p.points.begin(), p.points.end());
  for (const Arrow& a : overlay.arrows) extra.insert(extra.end(), {a.from, a.to});
  for (const Marker& m : overlay.markers) extra.push_back(m.position);
  for (const Vec3& p : extra) box.add(p);
  Framing f{box.centre(), farthest_distance(model, box.centre()), extra};
  if (before != nullptr) f.radius = std::max(f.radius, farthest_distance(*before, f.centre));
  for (const Vec3& p : extra) f.radius = std::max(f.radius, norm(p - f.centre));
  for (const deform::PointModel* m : {&model, before}) {
    if (m == nullptr) continue;
    for (std::size_t i = 0; i < m->size(); ++i) f.points.push_back(m->position(i));
  }
  return f;
}

// The grid of views: one view compares side by side, several put the before row above.
struct Grid {
  int columns;
  int rows;
  bool side_by_side;  // before and after in one row
};

Grid grid_of(const PictureRequest& r, bool compare) noexcept {
  const bool side_by_side = compare && r.views == 1;
  return {side_by_side ? 2 : r.views, side_by_side || !compare ? 1 : 2, side_by_side};
}

std::string view_label(const PictureRequest& r, bool compare, int row, int column) {
  std::string label;
  if (compare) label = row == 0 ? "before" : "after";
  if (r.views > 1 && !r.look) {
    double azimuth = std::fmod(r.azimuth_deg + 360.0 * column / r.views, 360.0);
    if (azimuth < 0.0) azimuth += 360.0;
    label += (label.empty() ? "" : ", ") + std::string("azimuth ") + std::to_string(std::lround(azimuth));
  }
  return label;
}

}  // namespace

long long picture_grid_pixels(const PictureRequest& request, bool compare) noexcept {
  const Grid grid = grid_of(request, compare);
  return static_cast<long long>(grid.columns) * request.view_width * grid.rows * request.view_height;
}

void check_picture_request(const PictureRequest& r, bool compare) {
  if (r.views < 1 || r.views > kMaxViews) {
    throw std::invalid_argument("views must be 1 to " + std::to_string(kMaxViews) + ", got " + std::to_string(r.views));
  }
  if (!std::isfinite(r.azimuth_deg) || !std::isfinite(r.elevation_deg)) {
    throw std::invalid_argument("azimuth and elevation must be finite");
  }
  if (r.look && (!is_finite(*r.look) || squared_norm(*r.look) == 0.0)) {
    throw std::invalid_argument("the view direction must be a finite, nonzero vector");
  }
  const long long pixels = picture_grid_pixels(r, compare);
  if (pixels > kMaxPicturePixels) {
    const Grid grid = grid_of(r, compare);
    throw std::invalid_argument(std::to_string(grid.columns) + " x " + std::to_string(grid.rows) + " views of " +
                                std::to_string(r.view_width) + "x" + std::to_string(r.view_height) + " make " +
                                std::to_string(pixels / 1000000) + " million pixels; a picture holds at most " +
                                std::to_string(kMaxPicturePixels / 1000000) +
                                " million: fewer views or a smaller size");
  }
}

Image render_picture(const deform::PointModel& model, const deform::PointModel* before, const PictureRequest& request,
                     PictureInfo* info) {
  const bool compare = before != nullptr;
  check_picture_request(request, compare);
  // Deformation moves points and keeps connectivity, but not every writer keeps the faces: an
  // after model without faces of its own is drawn with before's, so the two panels differ only
  // in what moved.
  const bool borrow_faces =
      compare && model.triangles.empty() && !before->triangles.empty() && before->size() == model.size();
  deform::PointModel with_faces;
  if (borrow_faces) {
    with_faces = model;
    with_faces.triangles = before->triangles;
  }
  RenderModel after_model(borrow_faces ? with_faces : model);
  std::vector<RenderModel> models;  // before (when comparing), then the model
  double max_displacement = 0.0;
  if (compare) {
    const std::vector<double> moved = displacement_magnitudes(*before, model);
    for (const double d : moved) max_displacement = std::max(max_displacement, d);
    after_model.set_colors(heat_colors(moved, max_displacement));
    models.emplace_back(*before);
  }
  models.push_back(std::move(after_model));

  const int w = request.view_width, h = request.view_height;
  const Framing framing = frame(model, before, request.overlay);
  const Vec3 up = axis_frame(request.up).up;
  const Vec3 first =
      request.look ? *request.look : look_direction(request.up, request.azimuth_deg, request.elevation_deg);
  const int label_scale = h >= 240 ? 2 : 1;
  const ColorBar bar{max_displacement, "displacement", request.unit, label_scale};
  const int bar_width = compare ? color_bar_width(bar) : 0;
  const Grid grid = grid_of(request, compare);
  const bool side_by_side = grid.side_by_side;
  const int columns = grid.columns;
  const int grid_rows = grid.rows;
  Image picture(columns * w + bar_width, grid_rows * h, request.lighting.background);

  // Labelled views keep the model out of a band as tall as the label, top and bottom alike.
  const bool labelled = !view_label(request, compare, 0, 0).empty();
  const int label_band = labelled ? text_height("a", label_scale) + 8 * label_scale : 0;
  const double margin = kMargin * h / std::max(1, h - 2 * label_band);
  ViewRenderer renderer(w, h, request.supersample);
  std::vector<Camera> cameras;
  for (int view = 0; view < request.views; ++view) {
    const Vec3 direction = turn(first, up, 360.0 * view / request.views);
    const Camera camera = tighten(fit_camera(framing.centre, framing.radius, direction, request.up, w, h),
                                  framing.points, framing.radius, margin);
    cameras.push_back(camera);
    for (std::size_t m = 0; m < models.size(); ++m) {
      const bool is_model = m + 1 == models.size();
      const Image image = renderer.render(models[m], camera, request.lighting, is_model ? request.overlay : Overlay{});
      const int x = (side_by_side ? static_cast<int>(m) : view) * w;
      const int y = (side_by_side ? 0 : static_cast<int>(m)) * h;
      picture.paste(image, x, y);
      const std::string label = view_label(request, compare, static_cast<int>(m), view);
      if (!label.empty()) draw_text(picture, x + 6 * label_scale, y + 4 * label_scale, label, kLabelInk, label_scale);
    }
  }
  if (compare) {
    const int margin = picture.height / 10;
    draw_color_bar(picture, columns * w, margin, picture.height - 2 * margin, bar);
  }
  if (info != nullptr) *info = {max_displacement, grid_rows, columns, std::move(cameras)};
  return picture;
}

}  // namespace sculpt::render
