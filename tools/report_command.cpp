// sculpt report: every approximation the station offers, measured against the exact
// computation on the user's own model and session (issue 11), as a table, a CSV and a Pareto
// plot of error against frame time.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <stdexcept>
#include <vector>

#include "commands.hpp"
#if SCULPT_HAS_LCM
#include "guard_report.hpp"
#include "json_report.hpp"
#include "output_paths.hpp"
#include "report/measure.hpp"
#include "report/pareto.hpp"
#include "report/report_files.hpp"
#include "report/session_log.hpp"
#include "sculpt/rt/scene.hpp"
#endif

namespace sculpt::tools {
namespace {

#if SCULPT_HAS_LCM
// The reduced model set's ratios (thesis 4.4.1).
constexpr double kReducedRatios[] = {0.05, 0.10, 0.25, 0.50};

class ReportCommand final : public Command {
 public:
  explicit ReportCommand(CLI::App& app) {
    sub_ = app.add_subcommand("report", "Error against run time: every approximation against the exact computation");
    sub_->add_option(
        "session", session_path_,
        "A session log written by sculpt run, or a scene (.toml) whose simulated session is recorded first "
        "(--quick: the bundled sphere)");
    sub_->add_option("--model", model_path_, "Run the session on this model instead of the scene's");
    sub_->add_option("--out", out_dir_, "Directory for report.md, report.csv and pareto.png")->required();
    sub_->add_option("--json", json_path_, "Write the rows here as JSON ('-' for stdout)");
    sub_->add_flag("--quick", quick_, "A short session on the bundled sphere (under a minute)");
  }
  bool chosen() const override { return sub_->parsed(); }

  int run() override {
    try {
      return run_report();
    } catch (const std::invalid_argument& e) {
      std::cerr << "sculpt report: error: " << e.what() << "\n";
      return kExitUsage;
    } catch (const std::exception& e) {
      std::cerr << "sculpt report: error: " << e.what() << "\n";
      return kExitFailure;
    }
  }

 private:
  int run_report() {
    if (session_path_.empty() && !quick_)
      throw std::invalid_argument("give a scene, or --quick for the bundled sphere");
    // --quick is the bundled sphere's session: beside another session it would be ignored.
    if (quick_ && !session_path_.empty()) {
      throw std::invalid_argument("--quick runs the bundled sphere's session; give " + session_path_ +
                                  " or --quick, not both");
    }
    if (session_path_.empty()) session_path_ = SCULPT_QUICK_SCENE;
    check_outputs(std::vector<NamedPath>{{"--json", json_path_}},
                  std::vector<NamedPath>{{"the session", session_path_}, {"the model (--model)", model_path_}});
    refuse_unwritable_folder({"--out", out_dir_});
    if (json_path_ == "-") reserve_stdout_for_json();
    const auto start = std::chrono::steady_clock::now();
    // A scene's session is recorded from its script; a log's is re-run from its own samples.
    const bool is_scene = lower_extension(session_path_) == ".toml";
    std::optional<report::LoggedSession> logged;
    if (!is_scene) logged = report::read_logged_session(session_path_);
    rt::Scene scene = is_scene ? rt::load_scene(session_path_) : logged->scene;
    const rt::SampleLog* samples = logged ? &logged->samples : nullptr;
    if (!model_path_.empty()) scene.model.path = model_path_;
    scene.heuristic.reduced_ratio = 1.0;  // the exact session is on the whole model
    std::filesystem::create_directories(out_dir_);

    const bool bar = isatty(STDERR_FILENO) != 0;
    const report::Progress progress = [bar](const std::string& what, std::size_t done, std::size_t total) {
      if (!bar) return;
      const std::size_t width = 30, filled = total ? done * width / total : width;
      std::fprintf(stderr, "\r%-16s [%s%s] %zu/%zu", what.c_str(), std::string(filled, '#').c_str(),
                   std::string(width - filled, ' ').c_str(), done, total);
      if (done == total) std::fputc('\n', stderr);
      std::fflush(stderr);
    };
    const report::RecordedSession as_run = report::record_session(scene, samples);
    const report::RecordedSession session = report::record_trajectory(scene, samples, as_run);
    std::fprintf(stderr, "recorded %s on %s: %zu steps\n", session_path_.c_str(), scene.model.path.c_str(),
                 session.steps.size());
    if (session.steps.empty()) throw std::runtime_error(session_path_ + ": the session never touched the model");
    report::ExactState exact_end;
    std::vector<report::Row> rows = report::per_frame_rows(session, exact_end, progress);
    std::vector<double> ratios(std::begin(kReducedRatios), std::end(kReducedRatios));
    for (report::Row& r : report::session_rows(scene, samples, as_run, exact_end, ratios, progress)) rows.push_back(r);
    report::mark_pareto_front(rows);

    const report::ReportContext context{session_path_, std::filesystem::path(scene.model.path).filename().string(),
                                        session.initial.size(), session.steps.size()};
    report::write_csv(out_dir_ + "/report.csv", rows);
    const std::string plot_note = report::plot_pareto(out_dir_, rows, context);
    if (!plot_note.empty()) std::fprintf(stderr, "sculpt report: no pareto.png: %s\n", plot_note.c_str());
    report::write_markdown(out_dir_ + "/report.md", rows, context, plot_note);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    print_table(rows);
    std::printf("%zu rows, %zu steps on %zu points in %.3g s; %s/report.md\n", rows.size(), session.steps.size(),
                session.initial.size(), seconds, out_dir_.c_str());
    if (!json_path_.empty()) write_json(json_path_, summary(rows, context, seconds, plot_note));
    return kExitOk;
  }

  static void print_table(const std::vector<report::Row>& rows) {
    std::printf("%-36s %-9s %9s %9s %10s %10s %8s %3s\n", "row", "kind", "median ms", "p99 ms", "mean err", "max err",
                "normal°", "P");
    for (const report::Row& r : rows) {
      std::printf("%-36s %-9s %9.4g %9.4g %10.3g %10.3g %8.3g %3s\n", r.name.c_str(), report::kind_name(r.kind),
                  r.median_ms, r.p99_ms, r.mean_error, r.max_error, r.max_normal_error_deg, r.pareto ? "*" : "");
    }
  }

  static nlohmann::json summary(const std::vector<report::Row>& rows, const report::ReportContext& c, double seconds,
                                const std::string& plot_note) {
    nlohmann::json doc = {{"session", c.session}, {"model", c.model},
                          {"points", c.points},   {"steps", c.steps},
                          {"seconds", seconds},   {"plot", plot_note.empty() ? "pareto.png" : ""}};
    stamp_summary(doc);
    doc["rows"] = nlohmann::json::array();
    for (const report::Row& r : rows) {
      doc["rows"].push_back({{"name", r.name},
                             {"group", r.group},
                             {"kind", report::kind_name(r.kind)},
                             {"frames", r.frames},
                             {"median_ms", r.median_ms},
                             {"p99_ms", r.p99_ms},
                             {"mean_error", r.mean_error},
                             {"max_error", r.max_error},
                             {"max_normal_error_deg", r.max_normal_error_deg},
                             {"max_displacement", r.max_displacement},
                             {"probe_inside", r.probe_inside},
                             {"guards", guards_json(r.guards)},
                             {"pareto", r.pareto}});
    }
    return doc;
  }

  CLI::App* sub_ = nullptr;
  std::string session_path_, model_path_, out_dir_, json_path_;
  bool quick_ = false;
};
#else
// Built without LCM: a report records and reads its sessions as event logs, so the command is
// there only to say how to get it.
class ReportCommand final : public Command {
 public:
  explicit ReportCommand(CLI::App& app) {
    sub_ = app.add_subcommand("report", "Error against run time (needs LCM; this build has none)");
    sub_->allow_extras();
  }
  bool chosen() const override { return sub_->parsed(); }
  int run() override {
    std::cerr << "sculpt report: error: the report records and reads sessions as event logs, which need LCM; "
                 "reconfigure with -DSCULPT_WITH_LCM=ON\n";
    return kExitFailure;
  }

 private:
  CLI::App* sub_ = nullptr;
};
#endif

}  // namespace

std::unique_ptr<Command> add_report_command(CLI::App& app) { return std::make_unique<ReportCommand>(app); }

}  // namespace sculpt::tools
