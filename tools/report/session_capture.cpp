#include "session_capture.hpp"

#include <memory>
#include <stdexcept>

#include "sculpt/hal/sim_script.hpp"
#include "sculpt/rt/replay_glove_source.hpp"
#include "sculpt/rt/station.hpp"
#include "sculpt/rt/station_setup.hpp"
#include "sculpt/rt/transfer.hpp"

namespace sculpt::tools::report {
namespace {

// Keeps what the report needs from the station's reports. Not on a real-time loop here (the
// ticks run in virtual time), so it may allocate.
class CaptureRecorder final : public rt::StationRecorder {
 public:
  explicit CaptureRecorder(RecordedSession& out) : out_(out) {}
  void glove_sample(const hal::GloveSample&) noexcept override {}
  void fingertips(std::uint64_t, std::span<const rt::FingerId>, std::span<const rt::FingerState>,
                  std::span<const bool>) noexcept override {}
  void haptic(const hal::HapticCommand&) noexcept override {}
  void tick(const rt::TickReport&, std::uint64_t, std::uint64_t, double) noexcept override {}
  void frame(const rt::FrameRecord& f) noexcept override {
    // A split step reports each of its frames with the step's probes: the step is taken once.
    if (!seen_ || f.tick != last_tick_) {
      out_.steps.emplace_back(f.probes.begin(), f.probes.end());
      const bool radius = f.settings->region.kind == deform::RegionSettings::Kind::kRadius;
      out_.step_radius.push_back(radius ? f.settings->region.radius : 0.0);
      out_.step_tick.push_back(f.tick);
    }
    seen_ = true;
    last_tick_ = f.tick;
    rt::append_frame_records(*f.report, *f.settings, f.frame_id, static_cast<std::int64_t>(f.tick), out_.records);
  }

 private:
  RecordedSession& out_;
  bool seen_ = false;
  std::uint64_t last_tick_ = 0;
};

// The script's samples as a glove would deliver them, stamped with their device time.
std::vector<hal::GloveSample> scripted_samples(const rt::Scene& scene) {
  if (scene.glove.config.backend != hal::Backend::kSim) {
    throw std::invalid_argument(scene.file +
                                ": sculpt report records a scene's session from its simulated glove "
                                "(glove.backend = \"sim\"); for another glove, give the log of its session");
  }
  hal::SimScript script(scene.glove.config.sim);
  if (!(script.end_time_s() < 1e6)) throw std::invalid_argument(scene.file + ": the glove script never ends");
  std::vector<hal::GloveSample> samples;
  hal::GloveSample s;
  const auto latency_ns = static_cast<std::int64_t>(scene.glove.config.sim.latency_ms * 1e6);
  while (script.next(s)) {
    s.receive_time_ns = static_cast<std::int64_t>(s.device_time_us) * 1000 + latency_ns;
    samples.push_back(s);
  }
  return samples;
}

}  // namespace

RecordedSession record_session(const rt::Scene& scene, const rt::SampleLog* samples) {
  RecordedSession out;
  auto source =
      std::make_unique<rt::ReplayGloveSource>(samples ? *samples : rt::SampleLog{scripted_samples(scene), {}});
  rt::ReplayGloveSource* replay = source.get();
  rt::StationSetup setup = rt::prepare_station(scene);
  out.initial = setup.model;
  out.spacing = setup.spacing.value;
  rt::Station station(setup.model, setup.settings, std::move(source), nullptr);
  out.settings = station.deformer().settings();
  CaptureRecorder recorder(out);
  station.set_recorder(&recorder);
  const auto period = static_cast<std::int64_t>(1e9 / setup.settings.rate_hz);
  const auto timeout = static_cast<std::int64_t>(setup.settings.glove_timeout_s * 1e9);
  const std::int64_t end = replay->last_time_ns() + timeout + 2 * period;
  // On past `end` while live ticks are still held back, a re-run tick each.
  for (std::int64_t t = replay->first_time_ns(); t <= end || !replay->finished();
       t = replay->next_tick_ns(t, period, timeout + 2 * period)) {
    replay->set_now(t);
    const rt::TickReport& r = station.tick(t, period);
    if (r.frame && r.collisions > 0) out.frame_ns.push_back(r.deform_ns);
  }
  out.guards = station.totals().guards;
  out.final_model = setup.model;
  return out;
}

RecordedSession record_trajectory(const rt::Scene& scene, const rt::SampleLog* samples, const RecordedSession& as_run) {
  rt::Scene global = scene;
  global.heuristic.region = rt::RegionChoice::kGlobal;
  RecordedSession out = record_session(global, samples);
  // The radius in force at a tick is the one of the session's last step at or before it.
  std::size_t k = 0;
  double radius = 0.0;
  for (std::size_t s = 0; s < out.steps.size(); ++s) {
    while (k < as_run.step_tick.size() && as_run.step_tick[k] <= out.step_tick[s]) radius = as_run.step_radius[k++];
    out.step_radius[s] = radius;
  }
  return out;
}

}  // namespace sculpt::tools::report
