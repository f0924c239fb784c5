// sculpt replay: a recorded session played back. Transfer (mode b) applies the logged collision
// events to a model without collision detection, for instance a session recorded on a reduced
// model applied to the full one; re-run (mode a) feeds the logged glove samples through the
// whole station in virtual time. Both together report how far the transfer is from the re-run.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <limits>
#include <optional>
#include <span>
#include <stdexcept>
#include <vector>

#include "bad_normals_option.hpp"
#include "commands.hpp"
#include "json_report.hpp"
#include "number_check.hpp"
#include "output_files.hpp"
#include "output_paths.hpp"
#include "recording_check.hpp"
#include "sculpt/deform/model_identity.hpp"
#include "sculpt/deform/model_io.hpp"
#include "sculpt/deform/normals.hpp"
#if SCULPT_HAS_LCM
#include "sculpt/logging/channels.hpp"
#include "sculpt/logging/event_log_reader.hpp"
#include "sculpt/logging/event_log_walk.hpp"
#include "sculpt/hal/lcm_messages.hpp"
#include "sculpt/logging/records.hpp"
#include "sculpt/logging/taken_ticks.hpp"
#include "sculpt/rt/lcm_session_header.hpp"
#include "sculpt/rt/log_edit.hpp"
#include "sculpt/rt/reduced_model.hpp"
#include "sculpt/rt/replay_glove_source.hpp"
#include "sculpt/rt/scene.hpp"
#include "sculpt/rt/session_header.hpp"
#include "sculpt/rt/session_recorder.hpp"
#include "sculpt/rt/station_setup.hpp"
#include "sculpt/rt/transfer.hpp"
#endif

namespace sculpt::tools {
namespace {

#if SCULPT_HAS_LCM
// Bytes that are not a valid event, or an event that does not decode, and where.
struct Damage {
  std::uint64_t offset = 0;
  std::string what;                   // "<path>: byte offset N: ..."
  std::size_t collisions_before = 0;  // collision events read before it
  std::size_t events_before = 0;      // valid events read before it
};

struct SessionLog {
  std::optional<rt::SessionHeader> header;
  std::vector<logging::CollisionRecord> collisions;
  std::vector<std::uint64_t> collision_offsets;  // byte offset of each collision event
  std::vector<hal::GloveSample> samples;
  logging::TakenTicks taken;  // which live tick took each sample
  std::size_t events = 0;
  std::size_t sculpt_events = 0;  // on glovesculpt's channels (SCULPT_...)
  std::string other_channel;      // the first channel that is not one of them
  std::vector<Damage> damage;     // in file order
  std::uint64_t skipped_bytes = 0;
  std::uint64_t size = 0;

  // Damage followed by a valid event: inside the log, not the cut a crash leaves at its end.
  const Damage* first_inner_damage() const {
    for (const Damage& d : damage) {
      if (d.events_before < events) return &d;
    }
    return nullptr;
  }
  // Where the cut at the end begins: the first damage no valid event follows.
  const Damage* tail_damage() const {
    for (const Damage& d : damage) {
      if (d.events_before == events) return &d;
    }
    return nullptr;
  }
};

// Reads everything replay needs, going on past what it cannot use and saying where that was.
SessionLog read_session(const std::string& path) {
  SessionLog log;
  const auto damaged = [&](std::uint64_t offset, std::string what) {
    log.damage.push_back({offset, std::move(what), log.collisions.size(), log.events});
    log.taken.damage();
  };
  // One valid event: true when it is one replay can use (or ignores by its channel), false
  // (and reported as damage) when it does not decode.
  const auto take = [&](const logging::LogEvent& event) {
    const std::string where = path + ": byte offset " + std::to_string(event.offset) + ": ";
    std::string error;
    if (event.channel == logging::kSessionChannel) {
      sculpt_lcm::session_header_t message;
      rt::SessionHeader header;
      if (log.events != 0) {
        damaged(event.offset, where + "a session header after the log's first event");
        return false;
      }
      if (!logging::decode(event, message, error) || !rt::from_lcm(message, header, error)) {
        damaged(event.offset, where + error);
        return false;
      }
      log.header = std::move(header);
    } else if (event.channel == logging::kCollisionChannel) {
      sculpt_lcm::collision_event_t message;
      logging::CollisionRecord record;
      if (!logging::decode(event, message, error)) {
        damaged(event.offset, where + error);
        return false;
      }
      if (!logging::from_lcm(message, record)) {
        damaged(event.offset, where + "SCULPT_COLLISION event with invalid fields");
        return false;
      }
      log.collisions.push_back(record);
      log.collision_offsets.push_back(event.offset);
    } else if (event.channel == logging::kGloveChannel) {
      sculpt_lcm::glove_sample_t message;
      hal::GloveSample sample;
      if (!logging::decode(event, message, error)) {
        damaged(event.offset, where + error);
        return false;
      }
      if (!hal::from_lcm(message, sample)) {
        damaged(event.offset, where + "SCULPT_GLOVE event with invalid fields");
        return false;
      }
      if (!logging::log_time_ns(message.utime, sample.receive_time_ns)) {  // the log's time base
        damaged(event.offset, where + "SCULPT_GLOVE event whose time (utime " + std::to_string(message.utime) +
                                  ") is before 1970 or after 2100");
        return false;
      }
      log.samples.push_back(sample);
      log.taken.sample();
    }
    log.taken.event(event.channel);
    return true;
  };
  const logging::EventLogTotals totals = logging::for_each_event(
      path,
      [&](const logging::LogEvent& event) {
        if (!take(event)) return;
        ++log.events;
        if (event.channel.rfind("SCULPT_", 0) == 0) {
          ++log.sculpt_events;
        } else if (log.other_channel.empty()) {
          log.other_channel = event.channel;
        }
      },
      damaged);
  log.size = totals.file_size;
  log.skipped_bytes = totals.skipped_bytes;
  return log;
}

const char* hand_name(std::uint8_t hand) { return hand == 0 ? "left" : "right"; }
const char* finger_name(std::uint8_t finger) {
  static const char* const kNames[] = {"thumb", "index", "middle", "ring", "little"};
  return finger < 5 ? kNames[finger] : "?";
}

// A progress line on a terminal (nothing otherwise). end() closes a line the work left short
// of 100 % (a transfer stopped at damage) or that a message is about to interrupt, so what is
// printed next starts a line of its own.
class ProgressLine {
 public:
  explicit ProgressLine(const char* what) : what_(what), tty_(isatty(STDERR_FILENO) != 0) {}
  ProgressLine(const ProgressLine&) = delete;
  ProgressLine& operator=(const ProgressLine&) = delete;
  ~ProgressLine() { end(); }

  void show(std::size_t done, std::size_t total) {
    if (!tty_ || total == 0) return;
    done = std::min(done, total);  // a re-run's held-back ticks run past the end it foresaw
    const int width = 40, filled = static_cast<int>(width * done / total);
    std::fprintf(stderr, "\r%-8s [%s%s] %3zu%%", what_, std::string(filled, '#').c_str(),
                 std::string(width - filled, ' ').c_str(), 100 * done / total);
    open_ = true;
    if (done == total) end();
  }
  void end() {
    if (open_) std::fputc('\n', stderr);
    open_ = false;
  }

 private:
  const char* what_;
  bool tty_;
  bool open_ = false;
};
#endif

class ReplayCommand final : public Command {
 public:
  explicit ReplayCommand(CLI::App& app) {
    sub_ = app.add_subcommand("replay", "Play a recorded session back onto a model");
    sub_->add_option("log", log_path_, "Event log written by sculpt run (LCM log format)")->required();
    auto* model = sub_->add_option("--model", model_path_, "Model to apply the session to (required unless --list)");
    auto* scene = sub_->add_option("--scene", scene_path_, "Scene of the session (needed to re-run the glove samples)");
    auto* mode = sub_->add_option("--mode", mode_,
                                  "transfer (apply the collision events) | rerun (glove samples through the station) | "
                                  "both")
                     ->check(CLI::IsMember({"transfer", "rerun", "both"}));
    auto* out = sub_->add_option("--out", out_path_, "Write the resulting model here (.ply, .off or .xyz)");
    sub_->add_option("--json", json_path_, "Write the report here ('-' for stdout)");
    auto* record = sub_->add_option("--record", record_path_, "Mode rerun: write the re-run's own durable log here");
    auto* replace_log =
        sub_->add_flag("--replace-log", replace_log_, "Let --record start afresh a log that holds an earlier session");
    replace_log->needs(record);
    auto* until =
        sub_->add_option("--until-frame", until_frame_, "Apply the collision frames up to and including this frame id")
            ->check(whole_in(0, std::numeric_limits<std::int64_t>::max()));
    auto* drop = sub_->add_option("--drop-stroke", drop_stroke_, "Leave out this stroke (its number in --list)")
                     ->check(whole_in(1, std::numeric_limits<std::int64_t>::max()));
    auto* list =
        sub_->add_flag("--list", list_, "Print the log's strokes (one finger's touch to release) with their frames");
    auto* force = sub_->add_flag("--force", force_, "Apply the log to a model it was not recorded on");
    sub_->add_flag("--skip-damage", skip_damage_,
                   "Go on past damage inside the log (the result is then a model no session produced)");
    auto* strict = sub_->add_flag("--strict", strict_,
                                  "Exit 3 when the log held damage (the model is still written; a crash's cut at the "
                                  "end is not damage)");
    bad_normals_.add_to(*sub_);
    // --list only prints the strokes (of the log recovered as replay would, so --skip-damage
    // and --json still apply): everything about a model would be ignored.
    for (CLI::Option* unused : {model, scene, mode, out, record, replace_log, until, drop, force, strict,
                                sub_->get_option("--bad-normals")}) {
      list->excludes(unused);
    }
  }
  bool chosen() const override { return sub_->parsed(); }

  int run() override {
#if SCULPT_HAS_LCM
    const bool edits = until_frame_ || drop_stroke_ > 0;
    if (mode_.empty()) mode_ = scene_path_.empty() || edits ? "transfer" : "both";
    try {
      check_arguments(edits);
      if (json_path_ == "-") reserve_stdout_for_json();
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
  // Everything the command line alone can refuse, before any work.
  void check_arguments(bool edits) {
    if (list_) return;
    if (model_path_.empty()) throw std::invalid_argument("--model is required (unless --list)");
    if (mode_ != "transfer" && scene_path_.empty()) {
      throw std::invalid_argument("--mode " + mode_ +
                                  " needs --scene (the session's filter, registration and settings)");
    }
    if (edits && mode_ != "transfer") {
      throw std::invalid_argument(
          "--until-frame and --drop-stroke edit the collision events: they need --mode transfer");
    }
    // The transfer applies the logged events alone; a scene given for it would be ignored.
    if (mode_ == "transfer" && !scene_path_.empty()) {
      throw std::invalid_argument(std::string("--scene is not used by --mode transfer") +
                                  (edits ? " (--until-frame and --drop-stroke transfer the edited events)" : "") +
                                  "; the scene is for --mode rerun and both");
    }
    if (!record_path_.empty() && mode_ != "rerun") throw std::invalid_argument("--record needs --mode rerun");
    if (!out_path_.empty()) refuse_unwritable_model_format("--out", out_path_);
    std::vector<NamedPath> inputs = {{"the log", log_path_}, { "the model (--model)", model_path_ }};
    if (!scene_path_.empty()) {
      inputs.push_back({"the scene (--scene)", scene_path_});
      inputs.push_back({"the scene's base model", rt::load_scene(scene_path_).model.path});
    }
    const NamedPath record{"--record", record_path_, /*device_allowed=*/true};  // a log may go to /dev/null
    const std::vector<NamedPath> outputs = {{"--out", out_path_}, {"--json", json_path_}, record};
    check_outputs(outputs, inputs);
    if (!record_path_.empty() && !replace_log_) refuse_overwriting_log({"--record", record_path_}, "--replace-log");
  }

  static SessionLog read_log(const std::string& path) {
    SessionLog log = read_session(path);
    if (log.size == 0) throw std::runtime_error(path + ": empty file, not an event log");
    if (log.events == 0) {
      throw std::runtime_error(path + ": not an event log: no valid LCM log event in its " + std::to_string(log.size) +
                               " bytes (" + log.damage.front().what.substr(path.size() + 2) + ")");
    }
    // Another program's LCM log (lcm-logger on any bus) reads cleanly and holds nothing to apply:
    // replaying it wrote the model unchanged, with exit 0 and a warning about missing headers.
    if (log.sculpt_events == 0) {
      throw std::runtime_error(path + ": not a glovesculpt log: none of its " + std::to_string(log.events) +
                               " LCM events is on a SCULPT_ channel (the first is on " + log.other_channel + ")");
    }
    return log;
  }

  int list_strokes(const SessionLog& log) {
    const std::vector<logging::CollisionRecord> events = recover(log, nullptr).events;
    nlohmann::json strokes = nlohmann::json::array();
    for (const rt::Stroke& s : rt::list_strokes(events)) {
      std::printf("stroke %-4zu %-5s %-6s  frames %lld-%lld  %zu events\n", s.number, hand_name(s.hand),
                  finger_name(s.finger), static_cast<long long>(s.first_frame), static_cast<long long>(s.last_frame),
                  s.events);
      strokes.push_back({{"stroke", s.number},
                         {"hand", s.hand},
                         {"finger", s.finger},
                         {"first_frame", s.first_frame},
                         {"last_frame", s.last_frame},
                         { "events",
                           s.events }});
    }
    if (!json_path_.empty()) {
      nlohmann::json json = {{"log", log_path_}, { "strokes", strokes }};
      stamp_summary(json);
      write_json(json_path_, json);
    }
    return kExitOk;
  }

  // What recovery decided about a log, for the decisions that follow (the JSON says the same
  // for its reader, with offsets and words).
  struct Recovery {
    std::vector<logging::CollisionRecord> events;  // the frames to apply
    bool stopped_at_damage = false;                // the events end before damage
    bool past_damage = false;                      // --skip-damage went on past damage
    bool cut = false;                              // the log ends in a crash's cut
    bool damaged() const noexcept { return stopped_at_damage || past_damage; }
  };

  // The events a crash or damage left whole: every complete frame up to a cut at the end (the
  // normal case after SIGKILL or a power cut), up to the last complete frame before damage
  // inside the log, or, with --skip-damage, every complete frame anywhere. Says what it left
  // out, with byte offsets, in `json` (when given) and on stderr.
  Recovery recover(const SessionLog& log, nlohmann::json* json) const {
    const std::span<const logging::CollisionRecord> all(log.collisions);
    std::span<const logging::CollisionRecord> events = all;
    std::optional<Damage> stop;  // damage inside the log, where replay stops
    if (const Damage* inner = log.first_inner_damage()) {
      stop = *inner;
      events = events.first(inner->collisions_before);
    }
    const rt::WholeFrames whole = rt::whole_frames(events);
    // A frame with more or fewer events than it says, and more after it, with no damage the
    // reader saw around it: damage too.
    if (whole.events < events.size() && !whole.cut_at_end && !stop) {
      const std::uint64_t at = log.collision_offsets[whole.events];
      stop = Damage{at,
                    log_path_ + ": byte offset " + std::to_string(at) + ": frame " +
                        std::to_string(events[whole.events].frame_id) + " has the wrong number of events",
                    whole.events, 0};
    }
    nlohmann::json damage = nlohmann::json::array();
    for (const Damage& d : log.damage) damage.push_back({{"offset", d.offset}, { "what", d.what }});
    nlohmann::json report = {{"skip_damage", skip_damage_},
                             {"damage", damage},
                             {"cut", nullptr},
                             {"stopped_at_damage", nullptr},
                             { "past_damage",
                               false }};
    Recovery r;
    std::vector<logging::CollisionRecord>& kept = r.events;
    if (stop && skip_damage_) {
      kept = rt::drop_incomplete_frames(all);
      r.past_damage = true;
      report["past_damage"] = true;
      std::fprintf(stderr,
                   "damage   %s\n         passed over (--skip-damage): the result is a model no session produced\n",
                   stop->what.c_str());
    } else {
      kept.assign(events.begin(), events.begin() + static_cast<std::ptrdiff_t>(whole.events));
      if (stop) {
        r.stopped_at_damage = true;
        report["stopped_at_damage"] = {{"offset", stop->offset}, { "what", stop->what }};
        std::fprintf(stderr,
                     "damage   %s\n         replay stops at the last complete frame before it "
                     "(--skip-damage goes on past it)\n",
                     stop->what.c_str());
      } else if (const Damage* tail = log.tail_damage(); whole.cut_at_end || tail) {
        // The normal end of a crashed session: a partial last event, or a frame whose last
        // events were never written.
        // The cut is where the last partial event begins, or the end of the file when the log
        // ends between two events of a frame.
        const std::uint64_t at = tail ? tail->offset : log.size;
        r.cut = true;
        nlohmann::json incomplete = nullptr;
        if (whole.cut_at_end) {
          incomplete = {{"frame", events[whole.events].frame_id},
                        {"offset", log.collision_offsets[whole.events]},
                        {"events", events.size() - whole.events},
                        { "frame_size",
                          events[whole.events].frame_size }};
        }
        report["cut"] = {{"offset", at}, { "incomplete_frame", incomplete }};
        std::fprintf(stderr,
                     "cut      %s ends at byte offset %llu (a crash or power cut): its %zu complete frames apply\n",
                     log_path_.c_str(), static_cast<unsigned long long>(at), whole.frames);
      }
    }
    report["last_frame"] = kept.empty() ? nlohmann::json(nullptr) : nlohmann::json(kept.back().frame_id);
    if (json) (*json)["recovery"] = report;
    return r;
  }

  // A logged frame the transfer cannot apply (its material out of range, or forces that would
  // put inf or NaN in the model: values no session logs, so damage the reader could not see) is
  // damage at its first event, as the reader's own: replay stops at the last frame before it,
  // or with --skip-damage passes over it. Returns whether to go on.
  bool pass_over_rejected_frame(const rt::FrameRejected& e, const SessionLog& log, Recovery& recovered,
                                nlohmann::json& json) const {
    const auto first = std::find_if(log.collisions.begin(), log.collisions.end(),
                                    [&](const logging::CollisionRecord& r) { return r.frame_id == e.frame_id(); });
    const std::uint64_t at = first == log.collisions.end()
                                 ? 0
                                 : log.collision_offsets[static_cast<std::size_t>(first - log.collisions.begin())];
    const std::string what = log_path_ + ": byte offset " + std::to_string(at) + ": frame " +
                             std::to_string(e.frame_id()) + " cannot be applied: " + e.why();
    nlohmann::json& recovery = json["recovery"];
    recovery["damage"].push_back({{"offset", at}, { "what", what }});
    json["skipped"].push_back(what);
    if (skip_damage_) {
      recovered.past_damage = true;
      recovery["past_damage"] = true;
      std::fprintf(stderr,
                   "damage   %s\n         passed over (--skip-damage): the result is a model no session produced\n",
                   what.c_str());
      return true;
    }
    recovered.stopped_at_damage = true;
    recovery["stopped_at_damage"] = {{"offset", at}, { "what", what }};
    std::fprintf(stderr,
                 "damage   %s\n         replay stops at the last complete frame before it (--skip-damage goes on "
                 "past it)\n",
                 what.c_str());
    return false;
  }

  // The model check of the session header: the recording model, or a reduced-set session's
  // full model; anything else only with --force.
  void check_model(const SessionLog& log, const deform::PointModel& model, nlohmann::json& json) const {
    const deform::ModelIdentity given = deform::model_identity(model);
    json["model_identity"] = {{"points", given.points}, { "hash", given.hash }};
    if (!log.header) {
      std::fprintf(
          stderr,
          "warning  %s has no session header (a log from before headers): the model cannot be checked against it\n",
          log_path_.c_str());
      json["model_match"] = "unchecked (no session header)";
      return;
    }
    const rt::SessionHeader& h = *log.header;
    json["session"] = {{"version", h.version},
                       {"scene", h.scene_path},
                       {"model",
                        { {"points", h.model.points},
                          { "hash",
                            h.model.hash } }},
                       {"reduced_ratio", h.full ? nlohmann::json(h.reduced_ratio) : nlohmann::json(nullptr)},
                       { "full_model",
                         h.full ? nlohmann::json{{"points", h.full->points},
                                                 { "hash",
                                                   h.full->hash }}
                                : nlohmann::json(nullptr) }};
    switch (rt::match_model(h, given)) {
      case rt::ModelMatch::kRecording:
        json["model_match"] = "recording";
        std::printf("model    the recording model (%s)\n", deform::describe(given).c_str());
        return;
      case rt::ModelMatch::kFull:
        json["model_match"] = "full";
        std::printf("model    the full model of a reduced-set session (ratio %g, recorded on %s): transfer\n",
                    h.reduced_ratio, deform::describe(h.model).c_str());
        return;
      case rt::ModelMatch::kOther: break;
    }
    std::string recorded = deform::describe(h.model);
    if (h.full) recorded += ", or its full model " + deform::describe(*h.full);
    if (!force_) {
      throw std::runtime_error(model_path_ + " (" + deform::describe(given) + ") is not the model " + log_path_ +
                               " was recorded on (" + recorded + "); --force applies it anyway");
    }
    json["model_match"] = "other (--force)";
    std::fprintf(stderr, "warning  %s (%s) is not the model the log was recorded on (%s): applied anyway (--force)\n",
                 model_path_.c_str(), deform::describe(given).c_str(), recorded.c_str());
  }

  int replay() {
    const auto start = std::chrono::steady_clock::now();
    const SessionLog log = read_log(log_path_);
    if (list_) return list_strokes(log);
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
                           { "skipped_bytes",
                             log.skipped_bytes }};
    stamp_summary(json);
    check_model(log, base, json);
    Recovery recovered = recover(log, &json);
    std::vector<logging::CollisionRecord>& events = recovered.events;
    bool produced_by_session = !recovered.past_damage;
    std::vector<std::string> skipped;
    for (const Damage& d : log.damage) skipped.push_back(d.what);
    json["skipped"] = skipped;
    if (drop_stroke_ > 0) {
      const std::vector<rt::Stroke> strokes = rt::list_strokes(events);
      if (drop_stroke_ > strokes.size()) {
        throw std::invalid_argument("--drop-stroke " + std::to_string(drop_stroke_) + ": the log has " +
                                    std::to_string(strokes.size()) + " strokes (see --list)");
      }
      const rt::Stroke& s = strokes[drop_stroke_ - 1];
      events = rt::drop_stroke(events, s);
      produced_by_session = false;
      json["dropped_stroke"] = {{"stroke", s.number},         {"hand", s.hand},
                                {"finger", s.finger},         {"first_frame", s.first_frame},
                                {"last_frame", s.last_frame}, { "events", s.events }};
      std::printf("undo     stroke %zu (%s %s, frames %lld-%lld, %zu events) left out\n", s.number, hand_name(s.hand),
                  finger_name(s.finger), static_cast<long long>(s.first_frame), static_cast<long long>(s.last_frame),
                  s.events);
    }
    if (until_frame_) {
      // Frame ids are the station's, not ticks or counts: a number past the log's last frame
      // (or before its first) is said, rather than applying everything (or nothing) silently.
      const rt::WholeFrames all = rt::whole_frames(events);
      const std::int64_t first = events.empty() ? -1 : events.front().frame_id;
      events = rt::until_frame(events, *until_frame_);
      const rt::WholeFrames kept = rt::whole_frames(events);
      if (all.frames == 0) {
        std::printf("until    frame %lld: the log holds no frame to apply\n", static_cast<long long>(*until_frame_));
      } else {
        std::printf("until    frame %lld: %zu of the log's %zu frames apply (its frames are %lld to %lld)\n",
                    static_cast<long long>(*until_frame_), kept.frames, all.frames, static_cast<long long>(first),
                    static_cast<long long>(all.last_frame));
      }
      json["until_frame"] = *until_frame_;
    }
    json["produced_by_a_session"] = produced_by_session;
    std::optional<deform::PointModel> transferred, rerun;
    std::optional<std::int64_t> transfer_last_frame;  // none: the transfer applied no frame
    if (mode_ != "rerun") {
      transferred = base;
      ProgressLine progress("transfer");
      const rt::TransferStats stats = rt::transfer(
          *transferred, events, [&](std::size_t d, std::size_t t) { progress.show(d, t); }, {},
          [&](const rt::FrameRejected& e) {
            progress.end();
            return pass_over_rejected_frame(e, log, recovered, json);
          });
      progress.end();
      if (stats.rejected > 0 && !stats.stopped) json["produced_by_a_session"] = false;
      transfer_last_frame = stats.last_frame;
      const nlohmann::json last = stats.last_frame ? nlohmann::json(*stats.last_frame) : nlohmann::json(nullptr);
      if (stats.stopped) json["recovery"]["last_frame"] = last;
      json["transfer"] = {{"frames", stats.frames}, {"events", stats.events}, {"rejected_frames", stats.rejected}, {
                            "last_frame",
                            last
                          }};
      std::printf("transfer %zu frames, %zu collision events onto %zu points\n", stats.frames, stats.events,
                  base.size());
    }
    if (mode_ != "transfer") {
      // A transfer that ended early (at damage, or at a crash's cut with a frame left
      // incomplete) is compared with a re-run of the same frames: the glove samples go on past
      // that frame, and a re-run of them all would compare two different sessions.
      std::optional<std::int64_t> until;
      if (transferred && (recovered.stopped_at_damage || recovered.cut)) until = transfer_last_frame.value_or(-1);
      rerun = rerun_session(log, json, until);
    }
    if (transferred && rerun) {
      const rt::ModelDifference d = rt::compare_models(*rerun, *transferred);
      json["difference"] = {{"mean", d.mean},
                            {"max", d.max},
                            {"relative_to", "bounding-box diagonal"},
                            {"mean_percent", 100.0 * d.mean},
                            { "max_percent",
                              100.0 * d.max }};
      std::printf(
          "compare  transfer vs re-run: mean %.4g %%, max %.4g %% of the bounding-box diagonal "
          "(the thesis measured 0.08 %% to 0.32 %% mean)\n",
          100.0 * d.mean, 100.0 * d.max);
    }
    const deform::PointModel& result = transferred ? *transferred : *rerun;
    if (!out_path_.empty()) {
      write_model_output(out_path_, result);
      std::printf("wrote    %s\n", out_path_.c_str());
    }
    // Damage is what --strict turns into a status: the reader's inside the log (stopped at or
    // passed over) and frames the transfer could not apply. A cut at the end is a crash's
    // normal trace, and its every complete frame applies.
    const bool damaged = recovered.damaged();
    json["damaged"] = damaged;
    json["time_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (!json_path_.empty()) write_json(json_path_, json);
    if (strict_ && damaged) {
      std::fprintf(stderr, "strict   %s held damage (above): exit %d\n", log_path_.c_str(), kExitDamage);
      return kExitDamage;
    }
    return record_complete_ ? kExitOk : kExitDamage;
  }

  // Mode a: the logged glove samples through the whole station, in virtual time, so the same
  // log, scene and model give the same result bit for bit. With --record, the re-run writes a
  // durable log of its own, as a live session would.
  // With `until`, the re-run stops after the tick that ran that frame (-1: before any frame).
  deform::PointModel rerun_session(const SessionLog& log, nlohmann::json& json, std::optional<std::int64_t> until) {
    rt::Scene scene = rt::load_scene(scene_path_);
    scene.model.path = model_path_;
    if (bad_normals_.given()) scene.model.bad_normals = bad_normals_.policy();
    scene.heuristic.reduced_ratio = 1.0;  // the re-run is on the model given, whole
    rt::StationSetup setup = rt::prepare_station(scene);
    // A station's log (it has a header) says which of its ticks took each sample.
    auto source = std::make_unique<rt::ReplayGloveSource>(
        rt::SampleLog{log.samples, log.header ? log.taken.finish() : std::vector<std::int64_t> {}});
    rt::ReplayGloveSource* replay = source.get();
    rt::Station station(setup.model, setup.settings, std::move(source), nullptr);
    std::unique_ptr<rt::SessionRecorder> recorder;
    if (!record_path_.empty()) {
      rt::Scene record_scene = scene;
      record_scene.output.log = record_path_;
      record_scene.lcm.publish = false;
      recorder = rt::make_session_recorder(record_scene, rt::session_header(record_scene, setup));
      station.set_recorder(recorder.get());
      recorder->start();
    }
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
    const auto timeout = static_cast<std::int64_t>(setup.settings.glove_timeout_s * 1e9);
    const std::int64_t end = last + timeout + 2 * period;
    const std::size_t total = static_cast<std::size_t>((end - first) / period + 1);
    std::size_t done = 0;
    ProgressLine progress("re-run");
    // On past `end` while live ticks are still held back, a re-run tick each.
    for (std::int64_t t = first; t <= end || !replay->finished();
         t = replay->next_tick_ns(t, period, timeout + 2 * period)) {
      if (until && station.next_frame_id() > *until) break;
      replay->set_now(t);
      const rt::TickReport& report = station.tick(t, period);
      if (recorder) recorder->tick(report, 0, 0, 0.0);
      const bool last_tick = t + period > end && replay->finished();
      if (++done % 1000 == 0 || last_tick) progress.show(static_cast<std::size_t>((t - first) / period), total);
    }
    progress.end();
    json["rerun"] = {{"ticks", station.totals().ticks},
                     {"frames", station.totals().frames},
                     { "collisions",
                       station.totals().collisions }};
    json["rerun"]["until_frame"] = until ? nlohmann::json(*until) : nlohmann::json(nullptr);
    json["rerun"]["next_frame"] = station.next_frame_id();
    if (until) {
      std::printf("re-run   stops after frame %lld, the transfer's last (the log ends early there)\n",
                  static_cast<long long>(*until));
    }
    if (recorder) {
      recorder->stop();
      const rt::RecordingCounts c = recorder->counts();
      json["rerun"]["record"] = {{"path", record_path_}, {"collisions", c.collisions}, {"dropped", c.log_dropped}, {
                                   "write_errors",
                                   c.write_errors
                                 }};
      record_complete_ = log_is_complete(c, "the re-run's model");
    }
    std::printf("re-run   %llu ticks, %llu frames, %llu collisions on %zu points\n",
                static_cast<unsigned long long>(station.totals().ticks),
                static_cast<unsigned long long>(station.totals().frames),
                static_cast<unsigned long long>(station.totals().collisions), setup.model.size());
    return setup.model;
  }
#endif

  CLI::App* sub_ = nullptr;
  std::string log_path_, model_path_, scene_path_, mode_, out_path_, json_path_, record_path_;
  std::optional<std::int64_t> until_frame_;
  std::size_t drop_stroke_ = 0;
  bool list_ = false, force_ = false, skip_damage_ = false, strict_ = false, replace_log_ = false;
  bool record_complete_ = true;  // --record wrote every event of the re-run
  BadNormalsOption bad_normals_;
};

}  // namespace

std::unique_ptr<Command> add_replay_command(CLI::App& app) { return std::make_unique<ReplayCommand>(app); }

}  // namespace sculpt::tools
