#include "bad_normals_option.hpp"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cstdio>

namespace sculpt::tools {

void BadNormalsOption::add_to(CLI::App& sub) {
  option_ = sub.add_option("--bad-normals", choice_,
                           "Zero or non-finite normals in the model file: reestimate (treat as missing) | refuse")
                ->check(CLI::IsMember({"reestimate", "refuse"}))
                ->default_val("reestimate");
}

deform::NormalPolicy BadNormalsOption::policy() const {
  return choice_ == "refuse" ? deform::NormalPolicy::kRefuse : deform::NormalPolicy::kReestimate;
}

bool BadNormalsOption::given() const { return option_ != nullptr && option_->count() > 0; }

deform::NormalReport BadNormalsOption::check(deform::PointModel& model, const std::string& path) const {
  const deform::NormalReport report = deform::check_normals(model, policy(), path);
  const std::string changed = deform::describe(report);
  if (!changed.empty()) std::fprintf(stderr, "%s: %s\n", path.c_str(), changed.c_str());
  return report;
}

nlohmann::json BadNormalsOption::to_json(const deform::NormalReport& report) const {
  return {{"policy", choice_}, {"zero_or_nonfinite", report.zero_or_nonfinite}, {"renormalised", report.renormalised}};
}

}  // namespace sculpt::tools
