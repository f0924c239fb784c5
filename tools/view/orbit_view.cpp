#include "orbit_view.hpp"

#include <algorithm>
#include <cmath>

namespace sculpt::view {
namespace {

double wrapped(double degrees) { return std::remainder(degrees, 360.0); }

double tilt_within(double degrees) { return std::clamp(degrees, -OrbitView::kMaxTiltDeg, OrbitView::kMaxTiltDeg); }

double zoom_within(double zoom) { return std::clamp(zoom, OrbitView::kMinZoom, OrbitView::kMaxZoom); }

}  // namespace

bool OrbitView::key(Key key) {
  ViewAngles next = now_;
  switch (key) {
    case Key::kOrbitLeft: next.azimuth_deg = wrapped(now_.azimuth_deg - kOrbitStepDeg); break;
    case Key::kOrbitRight: next.azimuth_deg = wrapped(now_.azimuth_deg + kOrbitStepDeg); break;
    case Key::kTiltUp: next.elevation_deg = tilt_within(now_.elevation_deg + kTiltStepDeg); break;
    case Key::kTiltDown: next.elevation_deg = tilt_within(now_.elevation_deg - kTiltStepDeg); break;
    case Key::kCloser: next.zoom = zoom_within(now_.zoom * kCloser); break;
    case Key::kFarther: next.zoom = zoom_within(now_.zoom / kCloser); break;
    case Key::kResetView: next = first_; break;
    default: return false;
  }
  return set(next);
}

bool OrbitView::drag(double dx, double dy, int width, int height) {
  if (!(width > 0 && height > 0) || !std::isfinite(dx) || !std::isfinite(dy)) return false;
  ViewAngles next = now_;
  next.azimuth_deg = wrapped(now_.azimuth_deg - kDragAcrossDeg * dx / width);
  next.elevation_deg = tilt_within(now_.elevation_deg + kDragDownDeg * dy / height);
  return set(next);
}

bool OrbitView::scroll(double notches) {
  if (!std::isfinite(notches)) return false;
  ViewAngles next = now_;
  next.zoom = zoom_within(now_.zoom * std::pow(kCloser, notches));
  return set(next);
}

bool OrbitView::set(const ViewAngles& next) {
  const bool changed =
      next.azimuth_deg != now_.azimuth_deg || next.elevation_deg != now_.elevation_deg || next.zoom != now_.zoom;
  now_ = next;
  return changed;
}

}  // namespace sculpt::view
