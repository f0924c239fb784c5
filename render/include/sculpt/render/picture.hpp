#pragma once
// The pictures `sculpt render` makes: a row of views around a model, optionally under a row of
// its earlier version with the displacement between them as a heat map and its colour bar.

#include <optional>
#include <string>
#include <vector>

#include "sculpt/deform/point_model.hpp"
#include "sculpt/render/camera.hpp"
#include "sculpt/render/image.hpp"
#include "sculpt/render/overlay.hpp"
#include "sculpt/render/view_renderer.hpp"

namespace sculpt::render {

struct PictureRequest {
  /// Each view's size in pixels; the picture is a grid of them (plus the colour bar).
  int view_width = 640;
  int view_height = 480;
  /// Views in a row, the i-th at azimuth + i * 360 / views.
  int views = 1;
  UpAxis up = UpAxis::kY;
  double azimuth_deg = 30.0;
  double elevation_deg = 20.0;
  /// When set, the (first) view looks along this direction instead of azimuth and elevation;
  /// further views turn about the up axis from it.
  std::optional<Vec3> look;
  Lighting lighting;
  /// Drawn over every view of the model (not of `before`).
  Overlay overlay;
  int supersample = 2;
  /// Shown under the colour bar: what the coordinates are measured in.
  std::string unit = "model units";
};

/// What was drawn, for the caller's summary.
struct PictureInfo {
  double max_displacement = 0.0;  ///< with `before` only
  int rows = 1;
  int columns = 1;
  std::vector<Camera> cameras;  ///< one per view, shared by before and after
};

/// The most pixels a picture's grid of views may hold (the colour bar aside): 64 megapixels,
/// 192 MB of RGB. Past it a request is refused before anything is drawn: a row of 36 views of
/// 4096 x 4096 would be a 1.8 GB picture, which few programs can open.
inline constexpr long long kMaxPicturePixels = 64000000;

/// The pixels of the grid of views `request` asks for, with or without a `before` model
/// (compare): one view compares side by side, several put a row of `before` above the row.
long long picture_grid_pixels(const PictureRequest& request, bool compare) noexcept;

/// Throws std::invalid_argument when `request` cannot be drawn: views out of 1 to 36, a
/// non-finite angle or view direction, or a grid past kMaxPicturePixels (the message gives its
/// size and the limit).
void check_picture_request(const PictureRequest& request, bool compare);

/// Renders `model` as asked, each view's camera fitted to the models' bounding sphere and then
/// tightened on their points (and the overlay's). With `before`, `before` and `model` are drawn from the same cameras
/// (fitted to both models together), `model` coloured by its displacement from `before`, with
/// a colour bar to the right: side by side for one view, a row of `before` above a row of
/// `model` for several. A `model` without faces is drawn with `before`'s when it has some. Throws std::invalid_argument for a request
/// check_picture_request refuses or models whose point counts differ, RenderError when no context can be made.
Image render_picture(const deform::PointModel& model, const deform::PointModel* before, const PictureRequest& request,
                     PictureInfo* info = nullptr);

}  // namespace sculpt::render
