// sculpt run: the station. Loads a scene, runs the fixed-rate loop until the duration, SIGINT
// or SIGTERM, then writes the sculpted model and a JSON summary.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <optional>
#include <thread>
#include <vector>

#include "commands.hpp"
#include "guard_report.hpp"
#include "json_report.hpp"
#include "lcm_url_option.hpp"
#include "number_check.hpp"
#include "output_files.hpp"
#include "output_paths.hpp"
#include "recording_check.hpp"
#include "sculpt/base/time_limits.hpp"
#include "sculpt/deform/model_io.hpp"
#include "sculpt/deform/normal_check.hpp"
#include "sculpt/rt/fixed_rate_loop.hpp"
#include "sculpt/rt/realtime_setup.hpp"
#include "sculpt/rt/scene.hpp"
#include "sculpt/rt/session_recorder.hpp"
#include "sculpt/rt/station_run.hpp"
#include "sculpt/rt/station_setup.hpp"
#include "serial_device_check.hpp"

namespace sculpt::tools {
namespace {

std::atomic<bool> g_stop{false};
extern "C" void on_signal(int) { g_stop.store(true); }

const char* glove_name(rt::GloveState s) {
  switch (s) {
    case rt::GloveState::kWaiting: return "waiting";
    case rt::GloveState::kLive: return "live";
    case rt::GloveState::kStale: return "stale";
  }
  return "?";
}

nlohmann::json histogram_json(const rt::LatencyHistogram& h) {
  return {{"count", h.count()},
          {"median_us", h.quantile(0.5) * 1e-3},
          {"p99_us", h.quantile(0.99) * 1e-3},
          {"p999_us", h.quantile(0.999) * 1e-3},
          {"max_us", static_cast<double>(h.max()) * 1e-3}};
}

class RunCommand final : public Command {
 public:
  explicit RunCommand(CLI::App& app) {
    sub_ = app.add_subcommand("run", "Run the sculpting station on a scene");
    sub_->add_option("scene", scene_path_, "Scene file (TOML)")->required();
    sub_->add_option("--duration", duration_s_, "Stop after this many seconds (default: until SIGINT/SIGTERM)")
        ->check(positive_up_to(base::kMaxDurationS, "seconds: at most a year"));
    sub_->add_option("--out", out_path_, "Write the final model here (overrides output.model)");
    sub_->add_option("--json", json_path_, "Write the run summary here (overrides output.json; '-' for stdout)");
    auto* serial = sub_->add_option("--serial", serial_device_,
                                    "Read the glove from this serial device (overrides glove.backend)");
    auto* lcm = sub_->add_option("--lcm", lcm_url_, "Read the glove from this LCM URL (overrides glove.backend)")
                    ->check(lcm_url_check());
    serial->excludes(lcm);  // one glove backend: the later would silently win
    sub_->add_flag("--quiet", quiet_, "No live status line");
    sub_->add_flag("--replace-log", replace_log_,
                   "Start the scene's event log (output.log) afresh even when it holds an earlier session");
  }
  bool chosen() const override { return sub_->parsed(); }

  int run() override {
    rt::Scene scene;
    try {
      scene = rt::load_scene(scene_path_);
    } catch (const std::exception& e) {
      std::cerr << "sculpt run: error: " << e.what() << "\n";
      return kExitUsage;
    }
    if (!serial_device_.empty()) {
      scene.glove.config.backend = hal::Backend::kSerial;
      scene.glove.config.serial.device = serial_device_;
    }
    if (!lcm_url_.empty()) {
      scene.glove.config.backend = hal::Backend::kLcm;
      scene.glove.config.lcm.url = lcm_url_;
    }
    // A serial line that cannot be one would run with 0 samples, or wait for ever in silence.
    if (const std::string problem = serial_problems(scene); !problem.empty()) {
      std::cerr << "sculpt run: error: " << problem << "\n";
      return kExitFailure;
    }
    // Outputs before the session: an unwritable format or an output that names an input would
    // otherwise only show once the work is done (or has overwritten the scene's model).
    try {
      const std::string out = !out_path_.empty() ? out_path_ : scene.output.model.value_or("");
      const std::string json = !json_path_.empty() ? json_path_ : scene.output.json.value_or("");
      const std::string log = scene.output.log.value_or("");
      // Each named as the user gave it: the option, or the scene's key it came from.
      const std::string out_name = !out_path_.empty() ? "--out" : "output.model";
      const std::string json_name = !json_path_.empty() ? "--json" : "output.json";
      if (!out.empty()) refuse_unwritable_model_format(out_name, out);
      const std::vector<NamedPath> inputs = {{"the scene", scene_path_}, {"the scene's base model", scene.model.path}};
      const std::vector<NamedPath> outputs = {
          {out_name, out}, {json_name, json}, {"output.log", log, /*device_allowed=*/true}};
      check_outputs(outputs, inputs);  // else found only once the session is over, its model lost
      if (!replace_log_) refuse_overwriting_log({scene_path_ + ": output.log", log}, "--replace-log");
      if (json == "-") reserve_stdout_for_json();
    } catch (const std::invalid_argument& e) {
      std::cerr << "sculpt run: error: " << e.what() << "\n";
      return kExitUsage;
    }
    try {
      return run_station(scene);
    } catch (const std::exception& e) {
      std::cerr << "sculpt run: error: " << e.what() << "\n";
      return kExitFailure;
    }
  }

 private:
  // The first serial device of the session (the glove's, the haptic sink's) that is missing or
  // not a terminal, named as the user gave it; empty when there is none.
  std::string serial_problems(const rt::Scene& scene) const {
    if (scene.glove.config.backend == hal::Backend::kSerial) {
      const std::string& device = scene.glove.config.serial.device;
      const std::string name =
          !serial_device_.empty() ? "--serial " + device : scene_path_ + ": glove.serial.device " + device;
      if (const std::string why = serial_device_problem(device); !why.empty()) return name + ": " + why;
    }
    if (scene.haptic.sink == hal::SinkKind::kSerial) {
      const std::string& device = scene.haptic.serial.device;
      if (const std::string why = serial_device_problem(device); !why.empty()) {
        return scene_path_ + ": haptic.serial.device " + device + ": " + why;
      }
    }
    return {};
  }

  int run_station(const rt::Scene& scene) {
    rt::StationSetup setup = rt::prepare_station(scene);
    std::unique_ptr<rt::Station> station = rt::make_station(setup, scene);
    std::printf("scene    %s\nmodel    %s: %zu points, normals %s, spacing %.4g (%s)\n", scene_path_.c_str(),
                scene.model.path.c_str(), setup.model.size(), setup.normals_source.c_str(), setup.spacing.value,
                setup.spacing.statistic.c_str());
    for (const std::string& note : setup.notes) std::printf("default  %s\n", note.c_str());
    const deform::NormalReport& normals = setup.normal_report;
    if (normals.zero_or_nonfinite + normals.renormalised > 0) {
      std::fprintf(stderr, "%s: %s\n", scene.model.path.c_str(), deform::describe(normals).c_str());
    }
    if (setup.calibration) {
      std::printf("register calibrated from %zu landmarks: rms residual %.4g, max %.4g\n",
                  scene.registration.landmarks.size(), setup.calibration->rms_residual,
                  setup.calibration->max_residual);
    }
    rt::RealtimeOptions rt_options;
    const bool require = scene.loop.realtime == rt::RealtimeMode::kRequire;
    rt_options.fifo = scene.loop.realtime != rt::RealtimeMode::kOff;
    rt_options.lock_memory = scene.loop.lock_memory || require;
    rt_options.cpu = scene.loop.cpu;
    rt_options.tight_timer_slack = true;  // no privilege needed; halves the wake-up lateness
    const std::vector<std::string> refused = rt::apply_realtime(rt_options);
    if (require) {
      if (const std::string why = rt::required_refusal(refused); !why.empty()) {
        throw std::runtime_error(scene_path_ + ": loop.realtime = \"require\", but " + why.substr(10) +
                                 " (run with CAP_SYS_NICE and CAP_IPC_LOCK, or set realtime = \"try\")");
      }
    }
    for (const std::string& warning : refused) std::fprintf(stderr, "warning  %s\n", warning.c_str());

    struct sigaction action {};
    action.sa_handler = on_signal;
    sigaction(SIGINT, &action, nullptr);
    sigaction(SIGTERM, &action, nullptr);
    g_stop.store(false);

    std::unique_ptr<rt::SessionRecorder> recorder = rt::make_session_recorder(scene, rt::session_header(scene, setup));
    station->set_recorder(recorder.get());
    station->start();  // first: a glove that fails to start leaves an earlier log (--replace-log) whole
    if (recorder) recorder->start();
    rt::FixedRateLoop loop(scene.loop.rate_hz);
    rt::LiveStatus live;
    std::atomic<bool> status_done{false};
    std::thread status([&] { show_status(live, status_done, loop.rate_hz()); });

    const std::int64_t start = rt::monotonic_now_ns();
    const std::int64_t end = duration_s_ > 0.0 ? start + static_cast<std::int64_t>(duration_s_ * 1e9) : INT64_MAX;
    rt::run_station(*station, loop, recorder.get(), live, end, g_stop);
    station->stop();
    if (recorder) recorder->stop();  // drains and flushes: nothing recorded is lost
    status_done.store(true);
    status.join();

    const std::string out = !out_path_.empty() ? out_path_ : scene.output.model.value_or("");
    // The session is over and its log closed: a model that cannot be written (a full disk) must
    // not also cost the summary, and the log still holds the session.
    std::string model_error;
    if (!out.empty()) {
      try {
        write_model_output(out, setup.model);
      } catch (const std::exception& e) {
        model_error = e.what();
      }
    }
    nlohmann::json summary = make_summary(*station, loop);
    summary["model_written"] = out.empty() ? nlohmann::json(nullptr) : nlohmann::json(model_error.empty());
    stamp_summary(summary);
    const std::optional<rt::RecordingCounts> recorded =
        recorder ? std::optional<rt::RecordingCounts>(recorder->counts()) : std::nullopt;
    if (recorded) summary["recording"] = recording_json(*recorded);
    summary["normals_checked"] = {{"zero_or_nonfinite", normals.zero_or_nonfinite},
                                  {"renormalised", normals.renormalised}};
    const std::string json = !json_path_.empty() ? json_path_ : scene.output.json.value_or("");
    if (!json.empty()) write_json(json, summary);
    const rt::StationTotals& t = station->totals();
    std::printf(
        "\nresult   %llu ticks at %.4g Hz, %llu overruns, tick median %.4g us p99 %.4g us p99.9 %.4g us "
        "max %.4g us (CPU p99.9 %.4g us max %.4g us)\n",
        static_cast<unsigned long long>(loop.stats().ticks), loop.achieved_rate(),
        static_cast<unsigned long long>(loop.stats().overruns), loop.stats().tick_time.quantile(0.5) * 1e-3,
        loop.stats().tick_time.quantile(0.99) * 1e-3, loop.stats().tick_time.quantile(0.999) * 1e-3,
        static_cast<double>(loop.stats().tick_time.max()) * 1e-3, loop.stats().tick_cpu_time.quantile(0.999) * 1e-3,
        static_cast<double>(loop.stats().tick_cpu_time.max()) * 1e-3);
    // A frame runs whenever a fingertip moved, touching or not: "frames" alone read as frames
    // with a collision ("24 collision frames, 9 collisions").
    std::printf(
        "         %llu glove samples, %llu frames (a fingertip moved), %llu of them with a collision, %llu "
        "collisions\n",
        static_cast<unsigned long long>(t.samples), static_cast<unsigned long long>(t.frames),
        static_cast<unsigned long long>(t.collision_frame_time.count()), static_cast<unsigned long long>(t.collisions));
    if (t.superseded_samples > 0) {  // else a glove faster than the loop looks fully used
      std::printf(
          "         %llu of them superseded by a newer sample of the same hand in their tick (the loop acts on the "
          "newest)\n",
          static_cast<unsigned long long>(t.superseded_samples));
    }
    if (t.out_of_range > 0) {  // a glove sending inf or 1e30 otherwise shows only as no collisions
      std::printf(
          "dropped  %llu glove samples or fingertips holding an inf or NaN or lying far outside the model "
          "(faults.out_of_range)\n",
          static_cast<unsigned long long>(t.out_of_range));
    }
    if (t.collision_frame_time.count() > 0) {
      std::printf("         deformation in frames with a collision: median %.4g us p99.9 %.4g us max %.4g us\n",
                  static_cast<double>(t.collision_frame_time.median()) * 1e-3,
                  static_cast<double>(t.collision_frame_time.quantile(0.999)) * 1e-3,
                  static_cast<double>(t.collision_frame_time.max()) * 1e-3);
    }
    if (model_error.empty() && !out.empty()) std::printf("wrote    %s\n", out.c_str());
    const std::string model = !model_error.empty() ? "the session's model"
                              : out.empty()        ? "the model"
                                                   : "the model written to " + out;
    const bool log_complete = !recorded || log_is_complete(*recorded, model);
    if (!model_error.empty()) {
      std::string recovery = "no event log was kept (output.log), so the session's model is lost";
      if (scene.output.log) {
        recovery = std::string(log_complete ? "the session is whole in its log" : "its log kept what it could") +
                   ": sculpt replay " + *scene.output.log + " --model " + scene.model.path + " --out " + out +
                   " writes it";
      }
      std::cerr << "sculpt run: error: " << model_error << "; " << recovery << "\n";
      return kExitFailure;
    }
    return log_complete ? kExitOk : kExitDamage;
  }

  static nlohmann::json recording_json(const rt::RecordingCounts& c) {
    nlohmann::json j = nlohmann::json::object();
    if (c.logging) {
      j["log"] = {{"path", c.log_path},
                  {"glove_samples", c.glove_samples},
                  {"fingertips", c.fingertips},
                  {"collisions", c.collisions},
                  {"ticks", c.ticks},
                  {"ticks_left_out", c.ticks_left_out},
                  {"haptic", c.haptic},
                  {"dropped", c.log_dropped},
                  {"write_errors", c.write_errors},
                  {"checks", c.log_checks}};
    }
    if (c.publishing) {
      j["live"] = {{"collisions", c.live_collisions},
                   {"ticks", c.live_ticks},
                   {"fingertips", c.live_fingertips},
                   {"dropped", c.live_dropped}};
    }
    return j;
  }

  void show_status(const rt::LiveStatus& live, const std::atomic<bool>& done, double rate) const {
    const bool tty = isatty(STDOUT_FILENO) && !quiet_;
    std::uint64_t last_ticks = 0;
    auto last = std::chrono::steady_clock::now();
    while (!done.load()) {
      std::this_thread::sleep_for(std::chrono::milliseconds(250));
      if (!tty) continue;
      const auto now = std::chrono::steady_clock::now();
      const double dt = std::chrono::duration<double>(now - last).count();
      const std::uint64_t ticks = live.ticks.load();
      std::printf("\r%7.4g/%g Hz  ticks %llu  overruns %llu  collisions %llu  region %llu pts in %.4g us  glove %s   ",
                  static_cast<double>(ticks - last_ticks) / dt, rate, static_cast<unsigned long long>(ticks),
                  static_cast<unsigned long long>(live.overruns.load()),
                  static_cast<unsigned long long>(live.collisions.load()),
                  static_cast<unsigned long long>(live.region_points.load()),
                  static_cast<double>(live.deform_ns.load()) * 1e-3,
                  glove_name(static_cast<rt::GloveState>(live.glove.load())));
      std::fflush(stdout);
      last_ticks = ticks;
      last = now;
    }
  }

  nlohmann::json make_summary(const rt::Station& station, const rt::FixedRateLoop& loop) const {
    const rt::LoopStats& s = loop.stats();
    const rt::StationTotals& t = station.totals();
    nlohmann::json per_finger = nlohmann::json::array();
    for (std::size_t i = 0; i < station.fingers().size(); ++i) {
      const rt::FingerId id = station.settings().fingers[i];
      per_finger.push_back({{"hand", id.hand}, {"finger", id.finger}, {"collisions", station.fingers()[i].collisions}});
    }
    const hal::SourceCounters c = station.glove_counters();
    nlohmann::json faults = {{"crc_errors", c.crc_errors},       {"framing_errors", c.framing_errors},
                             {"sequence_gaps", c.sequence_gaps}, {"overflows", c.overflows},
                             {"disconnects", c.disconnects},     {"reconnects", c.reconnects},
                             {"error_frames", c.error_frames},   {"bus_off", c.bus_off},
                             {"stale_events", t.stale_events},   {"out_of_range", t.out_of_range},
                             {"haptic_faults", t.haptic_faults}};
    return {{"scene", scene_path_},
            {"rate_hz", loop.rate_hz()},
            {"achieved_rate_hz", loop.achieved_rate()},
            {"ticks", s.ticks},
            {"overruns", s.overruns},
            {"missed_periods", s.missed_periods},
            {"tick_time", histogram_json(s.tick_time)},
            {"tick_cpu_time", histogram_json(s.tick_cpu_time)},
            {"wake_jitter", histogram_json(s.wake_jitter)},
            {"collision_frame_time", histogram_json(t.collision_frame_time)},
            {"glove_samples", c.samples},
            {"samples_taken", t.samples},
            {"samples_superseded", t.superseded_samples},
            {"stale_ticks", t.stale_ticks},
            {"frames", t.frames},
            {"collisions", t.collisions},
            {"collisions_per_finger", per_finger},
            {"max_region_points", t.max_region_points},
            {"max_region_radius", t.max_region_radius},
            {"index_rebuilds", t.index_rebuilds},
            {"faults", faults},
            {"guards", guards_json(t.guards)},
            {"haptic", haptic_json(station.haptic(), t, loop)}};
  }

  // What reached the glove's actuators: a serial line slower than the loop delivers fewer
  // commands than the loop sent (the newest per hand; the rest superseded), and says so here.
  // Per hand that touched, the rate while it did: commands the sink took per second in contact,
  // which the loop's rate bounds (a command every tick in contact), and of them those that
  // reached the link (a slow line carries the newest of several; idle and release frames, which
  // delivered_rate_hz counts, are not among them).
  static nlohmann::json haptic_json(const hal::HapticSink* sink, const rt::StationTotals& t,
                                    const rt::FixedRateLoop& loop) {
    if (!sink) return nullptr;
    const double rate = loop.achieved_rate();
    const double seconds = rate > 0.0 ? static_cast<double>(loop.stats().ticks) / rate : 0.0;
    nlohmann::json in_contact = nlohmann::json::array();
    for (std::size_t hand = 0; hand < t.contact_ticks.size(); ++hand) {
      if (t.contact_ticks[hand] == 0) continue;
      const double contact_s = rate > 0.0 ? static_cast<double>(t.contact_ticks[hand]) / rate : 0.0;
      const std::uint64_t delivered = sink->delivered_in_contact(hand);
      in_contact.push_back(
          {{"hand", hand},
           {"ticks", t.contact_ticks[hand]},
           {"commands", t.contact_commands[hand]},
           {"delivered", delivered},
           {"seconds", contact_s},
           {"rate_hz", contact_s > 0.0 ? static_cast<double>(t.contact_commands[hand]) / contact_s : 0.0},
           {"delivered_rate_hz", contact_s > 0.0 ? static_cast<double>(delivered) / contact_s : 0.0}});
    }
    return {{"sink", sink->name()},
            {"delivered", sink->delivered()},
            {"superseded", sink->superseded()},
            {"dropped", sink->dropped()},
            {"delivered_rate_hz", seconds > 0.0 ? static_cast<double>(sink->delivered()) / seconds : 0.0},
            {"in_contact", in_contact}};
  }

  CLI::App* sub_ = nullptr;
  std::string scene_path_, out_path_, json_path_, serial_device_, lcm_url_;
  double duration_s_ = 0.0;
  bool quiet_ = false;
  bool replace_log_ = false;
};

}  // namespace

std::unique_ptr<Command> add_run_command(CLI::App& app) { return std::make_unique<RunCommand>(app); }

}  // namespace sculpt::tools
