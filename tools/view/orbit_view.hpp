#pragma once
// Where the viewer's camera stands about the model: an azimuth about the up axis, an elevation
// above the horizon and a zoom on the fitted distance, moved by the keys and by the mouse. The
// camera is fitted once to the model as loaded and moves only by these: a view that refitted
// itself as the model changes would hide the change it is there to show.

#include "image_window.hpp"

namespace sculpt::view {

struct ViewAngles {
  double azimuth_deg = 30.0;
  double elevation_deg = 20.0;
  double zoom = 1.0;  ///< times the fitted distance
};

class OrbitView {
 public:
  static constexpr double kOrbitStepDeg = 15.0;  ///< a / d
  static constexpr double kTiltStepDeg = 10.0;   ///< w / s
  static constexpr double kMaxTiltDeg = 85.0;    ///< short of the poles, where "up" turns over
  static constexpr double kCloser = 0.8;         ///< z, or a wheel notch away from the user
  static constexpr double kMinZoom = 0.5, kMaxZoom = 4.0;
  static constexpr double kDragAcrossDeg = 180.0;  ///< a drag across the window's width turns this
  static constexpr double kDragDownDeg = 90.0;     ///< a drag down its height tilts this

  explicit OrbitView(const ViewAngles& first) : first_(first), now_(first) {}

  const ViewAngles& angles() const { return now_; }

  /// a and d orbit, w and s tilt, z and x move in and out by a fifth, r returns to the first
  /// view. False for any other key, or one that changes nothing (a tilt at its limit).
  bool key(Key key);

  /// A left-button drag of (dx, dy) pixels (right and down positive) in a width x height window
  /// turns the model as a hand on it would: right brings its left side into view (the camera
  /// orbits the other way), down brings its top (the camera rises). False when nothing moved.
  bool drag(double dx, double dy, int width, int height);

  /// Wheel notches, away from the user positive: each a fifth closer (or back). False when
  /// nothing moved (no notches, or the zoom at its limit).
  bool scroll(double notches);

 private:
  bool set(const ViewAngles& next);

  ViewAngles first_, now_;
};

}  // namespace sculpt::view
