#pragma once
// Where the station reports what it does, tick by tick: the durable log and the live channels.
// An interface so that rt does not depend on LCM; calls come from the loop, so implementations
// must be noexcept, allocation-free and only queue (the writing happens on their own threads).

#include <cstdint>
#include <span>

#include "sculpt/deform/deformer.hpp"
#include "sculpt/hal/glove_sample.hpp"
#include "sculpt/hal/haptic_sink.hpp"

namespace sculpt::rt {

struct FingerId;
struct FingerState;
struct TickReport;

/// One collision frame with what is needed to re-apply it without collision detection.
struct FrameRecord {
  std::uint64_t tick = 0;
  double time_s = 0.0;        ///< since the station started
  std::int64_t frame_id = 0;  ///< counts the frames of this run
  const deform::FrameReport* report = nullptr;
  const deform::DeformSettings* settings = nullptr;  ///< kernel, material, form, mode, region in force
  std::span<const FingerId> fingers;                 ///< the finger of report->contacts[k] is fingers[k]
  std::span<const deform::ProbeMotion> probes;
};

class StationRecorder {
 public:
  virtual ~StationRecorder() = default;
  virtual void glove_sample(const hal::GloveSample& sample) noexcept = 0;
  virtual void fingertips(std::uint64_t tick, std::span<const FingerId> ids, std::span<const FingerState> states,
                          std::span<const bool> accepted) noexcept = 0;
  virtual void frame(const FrameRecord& frame) noexcept = 0;
  virtual void haptic(const hal::HapticCommand& command) noexcept = 0;
  virtual void tick(const TickReport& report, std::uint64_t overruns, std::uint64_t missed_periods,
                    double tick_time_us) noexcept = 0;
};

}  // namespace sculpt::rt
