#pragma once
// The session recorder over LCM: the durable log and the live publisher. Built only with LCM.

#include <array>
#include <memory>
#include <optional>

#include "sculpt/logging/durable_log.hpp"
#include "sculpt/logging/lcm_publisher.hpp"
#include "sculpt/rt/session_recorder.hpp"
#include "sculpt/rt/tick_log_filter.hpp"

namespace sculpt::rt {

class LcmSessionRecorder final : public SessionRecorder {
 public:
  /// Takes the log's writer lock; start() writes `header` (when given) as the log's first event.
  LcmSessionRecorder(const Scene& scene, const std::optional<SessionHeader>& header);

  void start() override;
  void stop() override;
  void flush() override;
  RecordingCounts counts() const override;

  void glove_sample(const hal::GloveSample& sample) noexcept override;
  void fingertips(std::uint64_t tick, std::span<const FingerId> ids, std::span<const FingerState> states,
                  std::span<const bool> accepted) noexcept override;
  void frame(const FrameRecord& frame) noexcept override;
  void haptic(const hal::HapticCommand& command) noexcept override;
  void tick(const TickReport& report, std::uint64_t overruns, std::uint64_t missed_periods,
            double tick_time_us) noexcept override;

 private:
  std::unique_ptr<logging::DurableLog> log_;
  std::optional<SessionHeader> header_;  // written by start(), when the session begins
  std::unique_ptr<logging::LcmPublisher> publisher_;
  TickLogFilter log_ticks_;  // which ticks the durable log keeps (the live channel gets all)
  std::array<logging::CollisionRecord, deform::kMaxSources> collisions_{};  // one frame's, reused
};

}  // namespace sculpt::rt
