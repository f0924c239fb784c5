#pragma once
// The simulated glove's sample stream, computed from a SimConfig with no thread and no clock:
// the same config always gives the same stream, so tools and tests can replay it exactly.

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "sculpt/hal/backend_config.hpp"
#include "sculpt/hal/glove_sample.hpp"

namespace sculpt::hal {

/// Distance (glove units, metres by convention) from a scripted fingertip back to each of the
/// finger's other joints, which the script places on a straight line along -z behind the tip:
/// the nearest joint (DIP, or the thumb's IP) 0.02 behind, then 0.04, then 0.06 (fingers only).
/// Only the tips touch the model; the other joints exist so a sample looks like a glove's.
inline constexpr float kSimJointSpacing = 0.02f;

/// Where an unscripted finger's tip sits: 100 glove units up +z, far outside any model the
/// registration maps in, so it never collides. Finger f is offset by 0.02 * f along +x so the
/// points stay distinct; its other joints follow the same -z rule as a scripted finger's.
inline constexpr Point3f kSimRestTip = {0.0f, 0.0f, 100.0f};

/// Generates a simulated glove's samples in device-time order.
///
/// Every hand that has at least one scripted finger emits one positions-kind sample per tick
/// of 1 / rate_hz seconds, starting at device time 0; at the same tick hand 0 comes before
/// hand 1. A scripted fingertip follows its keyframes (linear interpolation, holding the first
/// before the first keyframe and the last after the last) plus Gaussian jitter per
/// coordinate. With `repeat`, all fingers loop together with the period of the latest
/// keyframe of the whole script, so a thumb and an index finger that squeeze stay in step.
///
/// The script ends after `duration_s`, or, when that is 0, at the latest keyframe (never with
/// `repeat`). Each hand's `sequence` counts every sample generated, dropped ones included, so
/// a dropout shows up downstream as a sequence gap. Random draws come from one
/// std::mt19937_64 seeded by `seed`: per sample a dropout draw (only if dropout_probability
/// > 0), then three jitter draws per scripted finger in finger order (only if jitter_stddev
/// > 0).
class SimScript {
 public:
  /// Validates and copies the config.
  /// @throw std::invalid_argument naming the field, e.g.
  ///   "glove.sim.finger[1].keyframes[3]: time goes backwards (0.5 s after 0.75 s)".
  explicit SimScript(const SimConfig& config);

  /// Writes the next sample (receive_time_ns left 0) and returns true; returns false once the
  /// script is over. noexcept and allocation-free.
  bool next(GloveSample& out) noexcept;

  /// Rewinds to device time 0 and reseeds, so the stream starts over identically.
  void reset() noexcept;

  /// The noise-free scripted tip of (hand, finger) at script time `t_s`, or false if that
  /// finger is not scripted.
  bool scripted_tip(std::uint8_t hand, std::uint8_t finger, double t_s, Point3f& out) const noexcept;

  /// Device time of the last sample, seconds; +infinity for an endless (repeating) script.
  double end_time_s() const noexcept { return end_time_s_; }
  /// Seconds between a hand's samples.
  double period_s() const noexcept { return 1.0 / rate_hz_; }
  /// Samples generated so far, dropped ones included.
  std::uint64_t generated() const noexcept { return generated_; }
  /// Samples dropped so far.
  std::uint64_t dropped() const noexcept { return dropped_; }
  /// True if `hand` has at least one scripted finger (and so emits samples).
  bool hand_active(std::uint8_t hand) const noexcept { return hand < kHands && active_[hand]; }

 private:
  static constexpr int kUnscripted = -1;

  Point3f interpolate(const std::vector<Keyframe>& keys, double t_s) const noexcept;
  void fill(std::uint8_t hand, double t_s, GloveSample& out) noexcept;

  double rate_hz_;
  std::uint64_t seed_;
  double jitter_stddev_;
  double dropout_probability_;
  bool repeat_;
  double loop_period_s_ = 0.0;  // latest keyframe of the whole script
  double end_time_s_ = 0.0;
  std::vector<std::vector<Keyframe>> scripts_;
  std::array<std::array<int, kFingers>, kHands> script_of_{};  // index into scripts_, or kUnscripted
  std::array<bool, kHands> active_{};

  std::mt19937_64 rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};
  std::uniform_real_distribution<double> uniform_{0.0, 1.0};
  std::uint64_t tick_ = 0;
  std::size_t hand_cursor_ = 0;  // next hand to consider within the current tick
  std::array<std::uint32_t, kHands> sequence_{};
  std::uint64_t generated_ = 0;
  std::uint64_t dropped_ = 0;
};

}  // namespace sculpt::hal
