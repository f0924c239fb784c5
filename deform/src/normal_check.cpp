#include "sculpt/deform/normal_check.hpp"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "sculpt/deform/model_io.hpp"
#include "sculpt/deform/normals.hpp"

namespace sculpt::deform {
namespace {

// "3,400": counts of points are read at a glance with their thousands grouped.
std::string grouped(std::size_t n) {
  const std::string digits = std::to_string(n);
  std::string out;
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}

std::string shown(const Vec3& n) {
  char buffer[96];
  std::snprintf(buffer, sizeof buffer, "(%g, %g, %g)", n.x, n.y, n.z);
  return buffer;
}

}  // namespace

NormalReport check_normals(PointModel& model, NormalPolicy policy, const std::string& name_for_errors) {
  NormalReport report;
  if (!model.has_normals()) return report;
  // Classify first, so a refusal leaves the model as it came.
  std::vector<std::uint32_t> bad;
  std::vector<std::uint32_t> off_unit;
  for (std::size_t i = 0; i < model.size(); ++i) {
    const Vec3 n = model.normal(i);
    const double length = norm(n);
    if (!std::isfinite(length) || length == 0.0) {
      if (policy == NormalPolicy::kRefuse) {
        throw ModelFileError(name_for_errors, "",
                             "vertex " + std::to_string(i) + " has a " + (length == 0.0 ? "zero" : "non-finite") +
                                 " normal " + shown(n));
      }
      bad.push_back(static_cast<std::uint32_t>(i));
    } else if (std::abs(length - 1.0) > kUnitNormalTolerance) {
      off_unit.push_back(static_cast<std::uint32_t>(i));
    }
  }
  for (const std::uint32_t i : off_unit) model.set_normal(i, normalized(model.normal(i)));
  reestimate_normals(model, bad);
  report.zero_or_nonfinite = bad.size();
  report.renormalised = off_unit.size();
  return report;
}

std::string describe(const NormalReport& report) {
  std::string line;
  if (report.zero_or_nonfinite > 0) {
    line = grouped(report.zero_or_nonfinite) + " zero or non-finite normal" +
           (report.zero_or_nonfinite == 1 ? "" : "s") + " re-estimated";
  }
  if (report.renormalised > 0) {
    if (!line.empty()) line += ", ";
    const char* noun = report.renormalised == 1 ? " normal" : " normals";
    line += grouped(report.renormalised) + (line.empty() ? noun : "") + " normalised";
  }
  return line;
}

}  // namespace sculpt::deform
