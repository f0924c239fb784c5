// sculpt check: issue 7's stability sweep of the deformation core. Runs degenerate single frames
// and long strokes over the material, kernel, weight-form, precision, G and scale axes, judges
// every frame with an oracle of its own (check/surface_side.hpp), checks the invariances that
// physics demands (check/invariants.hpp), prints one line per case and exits 1 when one fails.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "check/case_run.hpp"
#include "check/check_cases.hpp"
#include "commands.hpp"
#include "guard_report.hpp"
#include "json_report.hpp"
#include "output_paths.hpp"
#include "sculpt/deform/atomic_file.hpp"
#include "sculpt/deform/model_io.hpp"

namespace sculpt::tools {
namespace {

using nlohmann::json;

json number(double v) { return std::isfinite(v) ? json(v) : json(v > 0 ? "inf" : "nan"); }
json optional_number(const std::optional<double>& v) { return v ? number(*v) : json(nullptr); }

const char* kernel_name(deform::KernelKind k) { return k == deform::KernelKind::kKelvin ? "kelvin" : "regularized"; }

json case_json(const check::CaseResult& r) {
  const check::CaseSpec& c = *r.spec;
  const check::Metrics& m = r.metrics;
  const check::CaseSettings& s = c.settings;
  return {{"name", c.name},
          {"group", c.group},
          {"stroke", c.stroke},
          {"oracle", r.metrics.judged_by_mesh ? "mesh" : "pca"},
          {"settings",
           {{"nu", s.poisson_ratio},
            {"G", s.shear_modulus},
            {"kernel", kernel_name(s.kernel)},
            {"form", s.form == deform::WeightForm::kForce ? "force" : "scale"},
            {"precision", s.precision == deform::Precision::kFloat ? "float" : "double"},
            {"scale", s.scale},
            {"bc_factor", s.bc_factor}}},
          {"steps", m.steps},
          {"frames_applied", m.frames_applied},
          {"collisions", m.collisions},
          {"non_finite", m.non_finite},
          {"probe_inside", m.probe_inside},
          {"passed_through", m.passed_through},
          {"max_condition", number(m.max_condition)},
          {"max_relative_residual", number(m.max_relative_residual)},
          {"max_displacement_ratio", number(m.max_displacement_ratio)},
          {"min_jacobian", number(m.min_jacobian)},
          {"max_miss", number(m.max_miss)},
          {"deepest_after", number(m.deepest)},
          // The PCA plane's verdicts beside the mesh oracle's: diagnostics, not must-be-zero.
          {"pca_probe_inside", m.pca_probe_inside},
          {"pca_passed_through", m.pca_passed_through},
          {"pca_deepest_after", number(m.pca_deepest)},
          // The mesh's verdicts where the case has one (judging only where it is closed).
          {"mesh_probe_inside", c.mesh ? json(m.mesh_probe_inside) : json(nullptr)},
          {"mesh_passed_through", c.mesh ? json(m.mesh_passed_through) : json(nullptr)},
          {"mesh_deepest_after", c.mesh ? number(m.mesh_deepest) : json(nullptr)},
          {"guards", guards_json(m.guards)},
          {"invariants",
           {{"G", optional_number(r.g_deviation)},
            {"scale", optional_number(r.scale_deviation)},
            {"rigid", optional_number(r.rigid_deviation)},
            {"tolerance", r.tolerance}}},
          {"passed", r.failures.empty()},
          {"failures", r.failures},
          {"seconds", r.seconds}};
}

void print_header(std::FILE* out) {
  std::fprintf(out, "%-62s %9s %3s %3s %3s %8s %8s %8s  %s\n", "case", "frames", "nf", "in", "thr", "min det",
               "max miss", "inv dev", "guards / result");
}

void print_line(std::FILE* out, const check::CaseResult& r) {
  const check::Metrics& m = r.metrics;
  double dev = 0.0;
  bool any_dev = false;
  for (const auto& d : {r.g_deviation, r.scale_deviation, r.rigid_deviation}) {
    if (d) dev = std::max(dev, *d), any_dev = true;
  }
  char frames[32];
  std::snprintf(frames, sizeof frames, "%zu/%zu", m.steps, m.frames_applied);
  char devtext[16] = "-";
  if (any_dev) std::snprintf(devtext, sizeof devtext, "%.1e", dev);
  std::fprintf(out, "%-62s %9s %3u %3u %3u %8.3g %8.2e %8s ", r.spec->name.c_str(), frames, m.non_finite,
               m.probe_inside, m.passed_through, m.min_jacobian, m.max_miss, devtext);
  const std::string guards = acted_guards(m.guards, '=');
  std::fprintf(out, "%s", guards.empty() ? " -" : guards.c_str());
  if (r.failures.empty()) {
    std::fprintf(out, "  ok\n");
  } else {
    std::fprintf(out, "  FAIL:");
    for (const std::string& f : r.failures) std::fprintf(out, " [%s]", f.c_str());
    std::fprintf(out, "\n");
  }
}

class CheckCommand final : public Command {
 public:
  explicit CheckCommand(CLI::App& app) {
    sub_ = app.add_subcommand("check", "Stability sweep of the deformation core (issue 7); exit 1 when a check fails");
    sub_->add_flag("--quick", quick_, "Every axis to its extremes one at a time, a short scan series (< 40 s)");
    sub_->add_option("--json", json_path_, "Write the cases and a summary as JSON here ('-' for stdout)");
    sub_->add_option("--model", scan_path_, "Scan for the long push series [data/scans/snowden_54559.ply]")
        ->default_val(SCULPT_DEFAULT_SCAN);
    sub_->add_option("--case", filter_, "Run only the cases whose name contains this text");
  }

  bool chosen() const override { return sub_->parsed(); }

  int run() override {
    const auto start = std::chrono::steady_clock::now();
    // The JSON is written after every case has run (minutes): a folder given for it, or the scan
    // itself, is found before the first.
    try {
      check_outputs(std::vector<NamedPath>{{"--json", json_path_}},
                    std::vector<NamedPath>{{"the scan (--model)", scan_path_}});
    } catch (const std::invalid_argument& e) {
      std::cerr << "sculpt check: error: " << e.what() << "\n";
      return kExitUsage;
    }
    std::vector<check::CaseSpec> cases;
    try {
      cases = check::make_cases({quick_, scan_path_});
    } catch (const std::exception& e) {  // the scan: unreadable, or with no length scale (both named)
      std::cerr << "sculpt check: error: " << e.what() << "\n";
      return kExitFailure;
    }
    // Only the cases --case names run, and only they are counted: a filter that matched nothing
    // printed "606 cases, 0 failed" and passed with exit 0.
    const std::size_t all_cases = cases.size();
    std::erase_if(cases, [&](const check::CaseSpec& c) { return c.name.find(filter_) == std::string::npos; });
    if (cases.empty()) {
      std::cerr << "sculpt check: error: --case '" << filter_ << "' matches none of the " << all_cases
                << " case names (run without --case to see them)\n";
      return kExitUsage;
    }
    // The table goes to stderr when stdout carries the JSON.
    std::FILE* table = json_path_ == "-" ? stderr : stdout;
    print_header(table);
    const check::Tolerances tolerances;
    json out_cases = json::array();
    std::size_t failed = 0, skipped = 0;
    double worst_single = 0.0, worst_stroke = 0.0;
    for (const check::CaseSpec& c : cases) {
      if (!c.skipped.empty()) {
        std::fprintf(table, "%-62s skipped: %s\n", c.name.c_str(), c.skipped.c_str());
        out_cases.push_back({{"name", c.name}, {"group", c.group}, {"skipped", c.skipped}});
        ++skipped;
        continue;
      }
      const check::CaseResult r = check::run_case(c, tolerances);
      print_line(table, r);
      std::fflush(table);
      if (!r.failures.empty()) ++failed;
      for (const auto& d : {r.g_deviation, r.scale_deviation, r.rigid_deviation}) {
        if (d) (c.stroke ? worst_stroke : worst_single) = std::max(c.stroke ? worst_stroke : worst_single, *d);
      }
      out_cases.push_back(case_json(r));
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::fprintf(table,
                 "%zu cases, %zu failed, %zu skipped, %.3g s; worst invariant deviation %.2g (single frames, "
                 "tolerance %.0e), %.2g (strokes, tolerance %.0e)\n",
                 cases.size(), failed, skipped, seconds, worst_single, tolerances.single_frame, worst_stroke,
                 tolerances.stroke);
    if (!json_path_.empty()) {
      json doc = {{"cases", out_cases},
                  {"summary",
                   {{"quick", quick_},
                    {"case_filter", filter_},
                    {"cases", cases.size()},
                    {"failed", failed},
                    {"skipped", skipped},
                    {"seconds", seconds},
                    {"passed", failed == 0},
                    {"lengths", "base units: the case's model before scaling"},
                    {"tolerances",
                     {{"single_frame", tolerances.single_frame},
                      {"stroke", tolerances.stroke},
                      {"max_displacement_ratio", tolerances.max_displacement_ratio}}},
                    {"worst_deviation", {{"single_frame", worst_single}, {"stroke", worst_stroke}}}}}};
      stamp_summary(doc);
      if (json_path_ == "-") {
        std::cout << json_text(doc);
      } else {
        try {
          create_parent_folders(json_path_);
          deform::write_file_atomically(json_path_, json_text(doc));
        } catch (const std::exception& e) {
          std::cerr << "sculpt check: error: " << e.what() << "\n";
          return kExitFailure;
        }
      }
    }
    return failed == 0 ? kExitOk : kExitFailure;
  }

 private:
  CLI::App* sub_ = nullptr;
  bool quick_ = false;
  std::string json_path_, scan_path_, filter_;
};

}  // namespace

std::unique_ptr<Command> add_check_command(CLI::App& app) { return std::make_unique<CheckCommand>(app); }

}  // namespace sculpt::tools
