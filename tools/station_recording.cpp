#include "station_recording.hpp"

#include <nlohmann/json.hpp>

#include <stdexcept>

#include "sculpt/rt/fixed_rate_loop.hpp"
#include "sculpt/rt/station.hpp"
#if SCULPT_HAS_LCM
#include "sculpt/logging/durable_log.hpp"
#include "sculpt/logging/lcm_publisher.hpp"
#include "sculpt/rt/transfer.hpp"
#endif

namespace sculpt::tools {

#if SCULPT_HAS_LCM
namespace {

logging::Vec3f f3(const deform::Vec3& v) {
  return {static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z)};
}

class LcmRecording final : public Recording, public rt::StationRecorder {
 public:
  explicit LcmRecording(const rt::Scene& scene) {
    if (scene.output.log) {
      logging::DurableLogConfig config;
      config.path = *scene.output.log;
      config.flush_interval = std::chrono::milliseconds(static_cast<long>(scene.output.flush_interval_ms));
      log_ = std::make_unique<logging::DurableLog>(config);
    }
    if (scene.lcm.publish) {
      logging::PublisherConfig config;
      config.url = scene.lcm.url;
      publisher_ = std::make_unique<logging::LcmPublisher>(config);
    }
  }
  rt::StationRecorder* recorder() override { return this; }
  void start() override {
    if (log_) log_->start();
    if (publisher_) publisher_->start();
  }
  void stop() override {
    if (log_) log_->stop();
    if (publisher_) publisher_->stop();
  }
  void flush() override {
    if (log_) log_->flush_now();
  }
  std::uint64_t collisions_logged() const override {
    return log_ ? log_->counters()[logging::LogKind::kCollision].written : 0;
  }
  std::string summary_json() const override {
    nlohmann::json j = nlohmann::json::object();
    if (log_) {
      const logging::DurableLog::Counters c = log_->counters();
      j["log"] = {{"path", log_->path()},
                  {"glove_samples", c[logging::LogKind::kGlove].written},
                  {"fingertips", c[logging::LogKind::kFingertip].written},
                  {"collisions", c[logging::LogKind::kCollision].written},
                  {"ticks", c[logging::LogKind::kTick].written},
                  {"haptic", c[logging::LogKind::kHaptic].written},
                  {"dropped", c.dropped()},
                  {"write_errors", c.write_errors}};
    }
    if (publisher_) {
      const logging::PublisherCounters c = publisher_->counters();
      j["live"] = {{"collisions", c.collision.published}, {"ticks", c.tick.published},
                   {"fingertips", c.fingertip.published}, {"dropped", c.dropped()}};
    }
    return j.dump();
  }

  // --- StationRecorder (the loop's side: queue only) ---
  void glove_sample(const hal::GloveSample& s) noexcept override {
    // The log's time base is the wall clock (lcm-logplayer paces by it); the sample's receipt
    // is put on that base so a re-run sees it arrive when it did.
    const std::int64_t utime = logging::wall_time_us() - (rt::monotonic_now_ns() - s.receive_time_ns) / 1000;
    if (log_) log_->record(s, utime);
  }
  void fingertips(std::uint64_t tick, std::span<const rt::FingerId> ids, std::span<const rt::FingerState> states,
                  std::span<const bool> accepted) noexcept override {
    const std::int64_t utime = logging::wall_time_us();
    for (std::size_t i = 0; i < ids.size(); ++i) {
      if (!states[i].tracked) continue;
      logging::FingertipRecord r;
      r.utime = utime;
      r.tick = static_cast<std::int64_t>(tick);
      r.hand = ids[i].hand;
      r.finger = ids[i].finger;
      r.raw = f3(states[i].raw);
      r.filtered = f3(states[i].filtered);
      r.registered = f3(states[i].registered);
      r.accepted = accepted[i];
      r.in_contact = states[i].in_contact;
      if (log_) log_->record(r);
      if (publisher_) publisher_->publish(r);
    }
  }
  void frame(const rt::FrameRecord& f) noexcept override {
    const deform::FrameReport& report = *f.report;
    const deform::DeformSettings& s = *f.settings;
    const std::int64_t utime = logging::wall_time_us();
    for (std::size_t k = 0; k < f.fingers.size(); ++k) {
      const deform::ContactReport& c = report.contacts[k];
      if (c.state != deform::ProbeState::kCollided) continue;
      logging::CollisionRecord r = rt::collision_record(c, report, s, f.frame_id, static_cast<std::int64_t>(f.tick));
      r.utime = utime;
      r.time_s = f.time_s;
      r.hand = f.fingers[k].hand;
      r.finger = f.fingers[k].finger;
      if (log_) log_->record(r);
      if (publisher_) publisher_->publish(r);
    }
  }
  void haptic(const hal::HapticCommand& command) noexcept override {
    if (log_) log_->record(command, logging::wall_time_us());
  }
  void tick(const rt::TickReport& t, std::uint64_t overruns, std::uint64_t missed, double tick_time_us) noexcept override {
    logging::TickRecord r;
    r.utime = logging::wall_time_us();
    r.tick = static_cast<std::int64_t>(t.tick);
    r.tick_time_us = static_cast<float>(tick_time_us);
    r.budget_us = static_cast<float>(t.budget_ns * 1e-3);
    r.overruns = static_cast<std::int64_t>(overruns);
    r.missed_periods = static_cast<std::int64_t>(missed);
    r.region_points = static_cast<std::int32_t>(t.region_points);
    r.collisions = static_cast<std::int16_t>(t.collisions);
    r.glove_state = t.glove == rt::GloveState::kLive    ? sculpt_lcm::tick_stats_t::GLOVE_CONNECTED
                    : t.glove == rt::GloveState::kStale ? sculpt_lcm::tick_stats_t::GLOVE_STALE
                                                        : sculpt_lcm::tick_stats_t::GLOVE_CONNECTING;
    r.glove_age_ms = static_cast<float>(t.glove_age_ms);
    r.min_jacobian = static_cast<float>(t.min_jacobian);
    r.guards_acted = static_cast<std::int32_t>(t.guards.total());
    r.out_of_range = static_cast<std::int64_t>(t.out_of_range);
    if (log_) log_->record(r);
    if (publisher_) publisher_->publish(r);
  }

 private:
  std::unique_ptr<logging::DurableLog> log_;
  std::unique_ptr<logging::LcmPublisher> publisher_;
};

}  // namespace
#endif

std::unique_ptr<Recording> make_recording(const rt::Scene& scene) {
  if (!scene.output.log && !scene.lcm.publish) return nullptr;
#if SCULPT_HAS_LCM
  return std::make_unique<LcmRecording>(scene);
#else
  throw std::runtime_error("the scene asks for an event log or live publishing, which need LCM; "
                           "reconfigure with -DSCULPT_WITH_LCM=ON");
#endif
}

}  // namespace sculpt::tools
