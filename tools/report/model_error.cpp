#include "model_error.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace sculpt::tools::report {

ModelError model_error(const ExactState& exact, const deform::PointModel& other, double diagonal) {
  if (exact.size() != other.size()) throw std::invalid_argument("report: compared models differ in size");
  ModelError e;
  if (exact.size() == 0) return e;
  const double scale = diagonal > 0.0 ? 1.0 / diagonal : 1.0;
  double sum = 0.0;
  for (std::size_t i = 0; i < exact.size(); ++i) {
    const double d = norm(other.position(i) - exact.position[i]);
    sum += d;
    e.max = std::max(e.max, d);
  }
  e.mean = sum / static_cast<double>(exact.size()) * scale;
  e.max *= scale;
  if (exact.has_normals() && other.has_normals()) {
    // atan2 of |a x b| and a . b keeps the small angles float rounding makes (acos loses them).
    double worst = 0.0;
    for (std::size_t i = 0; i < exact.size(); ++i) {
      const deform::Vec3 a = exact.normal[i], b = other.normal(i);
      worst = std::max(worst, std::atan2(norm(cross(a, b)), dot(a, b)));
    }
    e.max_normal_deg = worst * 180.0 / std::numbers::pi;
  }
  return e;
}

}  // namespace sculpt::tools::report
