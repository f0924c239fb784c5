// sculpt replay: a recorded session played back. Transfer (mode b) applies the logged collision
// events to a model without collision detection, for instance a session recorded on a reduced
// model applied to the full one; re-run (mode a) feeds the logged glove samples through the
// whole station in virtual time. Both together report how far the transfer is from the re-run.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "bad_normals_option.hpp"
#include "commands.hpp"
#include "sculpt/deform/atomic_file.hpp"
#include "sculpt/deform/model_io.hpp"
#include "sculpt/deform/normals.hpp"
#if SCULPT_HAS_LCM
#include "sculpt/logging/channels.hpp"
#include "sculpt/logging/event_log_reader.hpp"
#include "sculpt/hal/lcm_messages.hpp"
#include "sculpt/logging/records.hpp"
#include "sculpt/rt/reduced_model.hpp"
#include "sculpt/rt/replay_glove_source.hpp"
#include "sculpt/rt/scene.hpp"
#include "sculpt/rt/station_setup.hpp"
#include "sculpt/rt/transfer.hpp"
#endif

namespace sculpt::tools {
namespace {

#if SCULPT_HAS_LCM
struct SessionLog {
  std::vector<logging::CollisionRecord> collisions;
  std::vector<hal::GloveSample> samples;
  std::size_t events = 0;
  std::vector<std::string> skipped;  // what was passed over, with byte offsets
  std::uint64_t skipped_bytes = 0;
};

// Reads everything replay needs, going on past what it cannot use and saying what that was.
SessionLog read_session(const std::string& path) {
  SessionLog log;
  logging::EventLogReader reader(path);
  logging::LogEvent event;
  for (;;) {
    const auto result = reader.next(event);
    if (result == logging::EventLogReader::Result::kEnd) break;
    if (result == logging::EventLogReader::Result::kCorrupt) {
      log.skipped.push_back(reader.error());
      continue;
    }
    ++log.events;
    std::string error;
    if (event.channel == logging::kCollisionChannel) {
      sculpt_lcm::collision_event_t message;
      logging::CollisionRecord record;
      if (!logging::decode(event, message, error)) {
        log.skipped.push_back(error);
      } else if (!logging::from_lcm(message, record)) {
        log.skipped.push_back(path + ": byte offset " + std::to_string(event.offset) +
                              ": SCULPT_COLLISION event with invalid fields");
      } else {
        log.collisions.push_back(record);
      }
    } else if (event.channel == logging::kGloveChannel) {
      sculpt_lcm::glove_sample_t message;
      hal::GloveSample sample;
      if (!logging::decode(event, message, error)) {
        log.skipped.push_back(error);
      } else if (!hal::from_lcm(message, sample)) {
        log.skipped.push_back(path + ": byte offset " + std::to_string(event.offset) +
                              ": SCULPT_GLOVE event with invalid fields");
      } else {
        sample.receive_time_ns = message.utime * 1000;  // the log's time base
        log.samples.push_back(sample);
      }
    }
  }
  log.skipped_bytes = reader.skipped_bytes();
  return log;
}

void progress_bar(const char* what, std::size_t done, std::size_t total) {
  if (!isatty(STDERR_FILENO) || total == 0) return;
  const int width = 40, filled = static_cast<int>(width * done / total);
  std::fprintf(stderr, "\r%-8s [%s%s] %3zu%%", what, std::string(filled, '#').c_str(),
               std::string(width - filled, ' ').c_str(), 100 * done / total);
  if (done == total) std::fprintf(stderr, "\n");
}
#endif

class ReplayCommand final : public Command {
 public:
  explicit ReplayCommand(CLI::App& app) {
    sub_ = app.add_subcommand("replay", "Play a recorded session back onto a model");
    sub_->add_option("log", log_path_, "Event log written by sculpt run (LCM log format)")->required();
    sub_->add_option("--model", model_path_, "Model to apply the session to")->required();
    sub_->add_option("--scene", scene_path_, "Scene of the session (needed to re-run the glove samples)");
    sub_->add_option("--mode", mode_, "transfer (apply the collision events) | rerun (glove samples through the station) | both")
        ->check(CLI::IsMember({"transfer", "rerun", "both"}));
    sub_->add_option("--out", out_path_, "Write the resulting model here");
    sub_->add_option("--json", json_path_, "Write the report here");
    bad_normals_.add_to(*sub_);
  }
  bool chosen() const override { return sub_->parsed(); }

  int run() override {
#if SCULPT_HAS_LCM
    if (mode_.empty()) mode_ = scene_path_.empty() ? "transfer" : "both";
    if (mode_ != "transfer" && scene_path_.empty()) {
      std::cerr << "sculpt replay: error: --mode " << mode_ << " needs --scene (the session's filter, registration and settings)\n";
      return kExitUsage;
    }
    try {
      return replay();
    } catch (const std::invalid_argument& e) {
      std::cerr << "sculpt replay: error: " << e.what() << "\n";
      return kExitUsage;
    } catch (const std::exception& e) {
      std::cerr << "sculpt replay: error: " << e.what() << "\n";
      return kExitFailure;
    }
#else
    std::cerr << "sculpt replay: error: reading event logs needs LCM; reconfigure with -DSCULPT_WITH_LCM=ON\n";
    return kExitFailure;
#endif
  }

 private:
#if SCULPT_HAS_LCM
  int replay() {
    const auto start = std::chrono::steady_clock::now();
    const SessionLog log = read_session(log_path_);
    for (const std::string& s : log.skipped) std::fprintf(stderr, "skipped  %s\n", s.c_str());
    deform::PointModel base = deform::read_model(model_path_);
    const deform::NormalReport normal_report = bad_normals_.check(base, model_path_);
    nlohmann::json json = {{"log", log_path_},
                           {"model", model_path_},
                           {"mode", mode_},
                           {"points", base.size()},
                           {"faces", base.triangles.size() / 3},
                           {"normals_checked", bad_normals_.to_json(normal_report)},
                           {"events", log.events},
                           {"collision_events", log.collisions.size()},
                           {"glove_samples", log.samples.size()},
                           {"skipped", log.skipped},
                           {"skipped_bytes", log.skipped_bytes}};
    std::optional<deform::PointModel> transferred, rerun;
    if (mode_ != "rerun") {
      transferred = base;
      const rt::TransferStats stats = rt::transfer(*transferred, log.collisions,
                                                   [](std::size_t d, std::size_t t) { progress_bar("transfer", d, t); });
      json["transfer"] = {{"frames", stats.frames}, {"events", stats.events}};
      std::printf("transfer %zu frames, %zu collision events onto %zu points\n", stats.frames, stats.events, base.size());
    }
    if (mode_ != "transfer") {
      rerun = rerun_session(log, json);
    }
    if (transferred && rerun) {
      const rt::ModelDifference d = rt::compare_models(*rerun, *transferred);
      json["difference"] = {{"mean", d.mean}, {"max", d.max}, {"relative_to", "bounding-box diagonal"},
                            {"mean_percent", 100.0 * d.mean}, {"max_percent", 100.0 * d.max}};
      std::printf("compare  transfer vs re-run: mean %.4f %%, max %.4f %% of the bounding-box diagonal "
                  "(the thesis measured 0.08 %% to 0.32 %% mean)\n", 100.0 * d.mean, 100.0 * d.max);
    }
    const deform::PointModel& result = transferred ? *transferred : *rerun;
    if (!out_path_.empty()) {
      const auto parent = std::filesystem::path(out_path_).parent_path();
      if (!parent.empty()) std::filesystem::create_directories(parent);
      deform::write_model(out_path_, result);
      std::printf("wrote    %s\n", out_path_.c_str());
    }
    json["time_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (!json_path_.empty()) deform::write_file_atomically(json_path_, json.dump(2) + "\n");
    if (!log.skipped.empty()) std::printf("skipped  %zu unreadable events (listed above)\n", log.skipped.size());
    return kExitOk;
  }

  // Mode a: the logged glove samples through the whole station, in virtual time, so the same
  // log, scene and model give the same result bit for bit.
  deform::PointModel rerun_session(const SessionLog& log, nlohmann::json& json) {
    rt::Scene scene = rt::load_scene(scene_path_);
    scene.model.path = model_path_;
    if (bad_normals_.given()) scene.model.bad_normals = bad_normals_.policy();
    scene.heuristic.reduced_ratio = 1.0;  // the re-run is on the model given, whole
    rt::StationSetup setup = rt::prepare_station(scene);
    auto source = std::make_unique<rt::ReplayGloveSource>(log.samples);
    rt::ReplayGloveSource* replay = source.get();
    rt::Station station(setup.model, setup.settings, std::move(source), nullptr);
    // The recorded frames' region radii, so an auto region does not depend on this machine's speed.
    // Indexed by frame id: frames that logged nothing (no collision) have no radius (0). A step
    // runs on an accepted glove sample and holds at most 64 frames, which bounds a sane id.
    std::vector<double> radii;
    const auto id_bound = static_cast<std::int64_t>(log.samples.size() + 1) * 64;
    for (const logging::CollisionRecord& c : log.collisions) {
      if (c.frame_id < 0 || c.frame_id > id_bound) continue;
      const auto id = static_cast<std::size_t>(c.frame_id);
      if (radii.size() <= id) radii.resize(id + 1, 0.0);
      radii[id] = c.region_radius;
    }
    if (!radii.empty() && setup.model.size() == 0) radii.clear();
    station.set_region_schedule(radii);
    const auto period = static_cast<std::int64_t>(1e9 / setup.settings.rate_hz);
    const std::int64_t first = replay->first_time_ns(), last = replay->last_time_ns();
    const std::int64_t end = last + static_cast<std::int64_t>(setup.settings.glove_timeout_s * 1e9) + 2 * period;
    const std::size_t total = static_cast<std::size_t>((end - first) / period + 1);
    std::size_t done = 0;
    for (std::int64_t t = first; t <= end; t += period) {
      replay->set_now(t);
      station.tick(t, period);
      if (++done % 1000 == 0 || t + period > end) progress_bar("re-run", done, total);
    }
    json["rerun"] = {{"ticks", station.totals().ticks}, {"frames", station.totals().frames},
                     {"collisions", station.totals().collisions}};
    std::printf("re-run   %llu ticks, %llu frames, %llu collisions on %zu points\n",
                static_cast<unsigned long long>(station.totals().ticks),
                static_cast<unsigned long long>(station.totals().frames),
                static_cast<unsigned long long>(station.totals().collisions), setup.model.size());
    return setup.model;
  }
#endif

  CLI::App* sub_ = nullptr;
  std::string log_path_, model_path_, scene_path_, mode_, out_path_, json_path_;
  BadNormalsOption bad_normals_;
};

}  // namespace

std::unique_ptr<Command> add_replay_command(CLI::App& app) { return std::make_unique<ReplayCommand>(app); }

}  // namespace sculpt::tools
