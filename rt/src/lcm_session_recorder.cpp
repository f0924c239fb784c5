#include "lcm_session_recorder.hpp"

#include "sculpt/rt/collision_records.hpp"
#include "sculpt/rt/fixed_rate_loop.hpp"
#include "sculpt/rt/lcm_session_header.hpp"
#include "sculpt/rt/station.hpp"

namespace sculpt::rt {
namespace {

logging::Vec3f f3(const deform::Vec3& v) {
  return {static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z)};
}

}  // namespace

LcmSessionRecorder::LcmSessionRecorder(const Scene& scene, const std::optional<SessionHeader>& header)
    : log_ticks_(tick_log_interval(scene.output.tick_interval_ms, scene.loop.rate_hz), 0.5e6 / scene.loop.rate_hz) {
  if (scene.output.log) {
    logging::DurableLogConfig config;
    config.path = *scene.output.log;
    config.flush_interval = std::chrono::milliseconds(static_cast<long>(scene.output.flush_interval_ms));
    log_ = std::make_unique<logging::DurableLog>(config);
    header_ = header;
  }
  if (scene.lcm.publish) {
    logging::PublisherConfig config;
    config.url = scene.lcm.url;
    publisher_ = std::make_unique<logging::LcmPublisher>(config);
  }
}

void LcmSessionRecorder::start() {
  if (log_ && header_) log_->write_session_header(to_lcm(*header_, logging::wall_time_us()));
  if (log_) log_->start();
  if (publisher_) publisher_->start();
}

void LcmSessionRecorder::stop() {
  if (log_) log_->stop();
  if (publisher_) publisher_->stop();
}

void LcmSessionRecorder::flush() {
  if (log_) log_->flush_now();
}

RecordingCounts LcmSessionRecorder::counts() const {
  RecordingCounts r;
  if (log_) {
    const logging::DurableLog::Counters c = log_->counters();
    r.logging = true;
    r.log_path = log_->path();
    r.glove_samples = c[logging::LogKind::kGlove].written;
    r.fingertips = c[logging::LogKind::kFingertip].written;
    r.collisions = c[logging::LogKind::kCollision].written;
    r.ticks = c[logging::LogKind::kTick].written;
    r.ticks_left_out = log_ticks_.left_out();
    r.haptic = c[logging::LogKind::kHaptic].written;
    r.log_dropped = c.dropped();
    r.write_errors = c.write_errors;
    r.log_checks = c.checks;
  }
  if (publisher_) {
    const logging::PublisherCounters c = publisher_->counters();
    r.publishing = true;
    r.live_collisions = c.collision.published;
    r.live_ticks = c.tick.published;
    r.live_fingertips = c.fingertip.published;
    r.live_dropped = c.dropped();
  }
  return r;
}

void LcmSessionRecorder::glove_sample(const hal::GloveSample& s) noexcept {
  // The log's time base is the wall clock (lcm-logplayer paces by it); the sample's receipt is
  // put on that base so a re-run sees it arrive when it did.
  const std::int64_t utime = logging::wall_time_us() - (monotonic_now_ns() - s.receive_time_ns) / 1000;
  if (log_) log_->record(s, utime);
}

void LcmSessionRecorder::fingertips(std::uint64_t tick, std::span<const FingerId> ids,
                                    std::span<const FingerState> states, std::span<const bool> accepted) noexcept {
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

void LcmSessionRecorder::frame(const FrameRecord& f) noexcept {
  const std::size_t n = frame_collision_records(f, collisions_);
  const std::int64_t utime = logging::wall_time_us();
  for (std::size_t k = 0; k < n; ++k) {
    collisions_[k].utime = utime;
    if (log_) log_->record(collisions_[k]);
    if (publisher_) publisher_->publish(collisions_[k]);
  }
}

void LcmSessionRecorder::haptic(const hal::HapticCommand& command) noexcept {
  if (log_) log_->record(command, logging::wall_time_us());
}

void LcmSessionRecorder::tick(const TickReport& t, std::uint64_t overruns, std::uint64_t missed,
                              double tick_time_us) noexcept {
  logging::TickRecord r;
  r.utime = logging::wall_time_us();
  r.tick = static_cast<std::int64_t>(t.tick);
  r.tick_time_us = static_cast<float>(tick_time_us);
  r.budget_us = static_cast<float>(t.budget_ns * 1e-3);
  r.overruns = static_cast<std::int64_t>(overruns);
  r.missed_periods = static_cast<std::int64_t>(missed);
  r.region_points = static_cast<std::int32_t>(t.region_points);
  r.collisions = static_cast<std::int16_t>(t.collisions);
  r.glove_state = t.glove == GloveState::kLive    ? sculpt_lcm::tick_stats_t::GLOVE_CONNECTED
                  : t.glove == GloveState::kStale ? sculpt_lcm::tick_stats_t::GLOVE_STALE
                                                  : sculpt_lcm::tick_stats_t::GLOVE_CONNECTING;
  r.glove_age_ms = static_cast<float>(t.glove_age_ms);
  r.min_jacobian = static_cast<float>(t.min_jacobian);
  r.guards_acted = static_cast<std::int32_t>(t.guards.total());
  r.out_of_range = static_cast<std::int64_t>(t.out_of_range);
  if (log_ && log_ticks_.keep(t, overruns, missed, tick_time_us)) log_->record(r);
  if (publisher_) publisher_->publish(r);
}

}  // namespace sculpt::rt
