#include "sculpt/deform/settings_range.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <utility>
#include <vector>

namespace sculpt::deform {
namespace {

[[noreturn]] void refuse(const std::ostringstream& text) { throw std::invalid_argument(text.str()); }

void append_limit(std::ostringstream& text, const ModelExtent& extent) {
  text << ", more than " << kMaxDiagonals << " bounding-box diagonals of the model (its diagonal is " << extent.diagonal
       << ")";
}

}  // namespace

ModelExtent ModelExtent::of(const PointModel& model) {
  ModelExtent e;
  if (model.empty()) return e;
  auto range = [](const std::vector<float>& v) {
    const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
    return std::pair<double, double>(*lo, *hi);
  };
  const auto [x0, x1] = range(model.x);
  const auto [y0, y1] = range(model.y);
  const auto [z0, z1] = range(model.z);
  e.centre = {0.5 * (x0 + x1), 0.5 * (y0 + y1), 0.5 * (z0 + z1)};
  e.diagonal = model.bounding_box_diagonal();
  return e;
}

void check_length_against_model(const std::string& name, double value, LengthRule rule, const ModelExtent& extent) {
  // Streams print %g-style: 1e-09 stays 1e-09 rather than the 0.000000 of std::to_string.
  std::ostringstream text;
  text << name << " = " << value;
  if (!std::isfinite(value)) {
    text << " must be a finite number";
    refuse(text);
  }
  if (rule == LengthRule::kPositive ? !(value > 0.0) : !(value >= 0.0)) {
    text << (rule == LengthRule::kPositive ? " must be > 0" : " must be >= 0");
    refuse(text);
  }
  if (value > kMaxDiagonals * extent.diagonal) {
    text << " is too large";
    append_limit(text, extent);
    refuse(text);
  }
}

void check_position_against_model(const std::string& name, const Vec3& position, const ModelExtent& extent) {
  std::ostringstream text;
  text << name << ": (" << position.x << ", " << position.y << ", " << position.z << ")";
  if (!is_finite(position)) {
    text << " is not finite";
    refuse(text);
  }
  // std::hypot scales: a coordinate of 1e300 is 1e300 away, where the sum of squares would
  // overflow and the message read "inf from the model's centre".
  const Vec3 d = position - extent.centre;
  const double distance = std::hypot(d.x, d.y, d.z);
  if (!(distance <= kMaxDiagonals * extent.diagonal)) {
    text << " is " << distance << " from the model's centre";
    append_limit(text, extent);
    refuse(text);
  }
}

void check_settings_against_model(const DeformSettings& settings, const PointModel& model, const SettingNames& names) {
  const ModelExtent extent = ModelExtent::of(model);
  const ContactSettings& c = settings.contact;
  check_length_against_model(names.bc_radius, c.bc_radius, LengthRule::kPositive, extent);
  check_length_against_model(names.min_source_distance, c.min_source_distance, LengthRule::kPositive, extent);
  check_length_against_model(names.guard_distance, c.guard_distance, LengthRule::kNonNegative, extent);
  if (settings.region.kind == RegionSettings::Kind::kRadius) {
    check_length_against_model(names.region_radius, settings.region.radius, LengthRule::kPositive, extent);
  }
  // 0 means "the bc radius" (RegionSettings).
  check_length_against_model(names.border_width, settings.region.border_width, LengthRule::kNonNegative, extent);
  if (settings.kernel.kind == KernelKind::kRegularized) {
    check_length_against_model(names.regularization, settings.kernel.regularization, LengthRule::kPositive, extent);
  }
}

}  // namespace sculpt::deform
