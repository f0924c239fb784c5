#include "sculpt/hal/sim_script.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "sculpt/base/number_text.hpp"
#include "sculpt/base/time_limits.hpp"

namespace sculpt::hal {
namespace {

constexpr double kMinRateHz = 1.0;
constexpr double kMaxRateHz = 10000.0;

[[noreturn]] void fail(const std::string& field, const std::string& why) {
  throw std::invalid_argument("glove.sim." + field + ": " + why);
}

std::string number(double v) { return base::number_text(v); }

std::string finger_field(std::size_t i) { return "finger[" + std::to_string(i) + "]"; }

// Writes a straight finger whose tip is `tip`, the other joints behind it along -z.
void place_finger(std::size_t finger, const Point3f& tip, GloveSample& out) noexcept {
  const std::size_t last = kTipJoint[finger];
  const std::size_t first = finger == 0 ? 0 : kTipJoint[finger - 1] + 1;
  for (std::size_t j = first; j <= last; ++j) {
    const auto behind = static_cast<float>(last - j);
    out.joints[j] = {tip[0], tip[1], tip[2] - behind * kSimJointSpacing};
  }
}

}  // namespace

SimScript::SimScript(const SimConfig& config)
    : rate_hz_(config.rate_hz),
      seed_(config.seed),
      jitter_stddev_(config.jitter_stddev),
      dropout_probability_(config.dropout_probability),
      repeat_(config.repeat),
      rng_(config.seed) {
  if (!(config.rate_hz >= kMinRateHz && config.rate_hz <= kMaxRateHz))
    fail("rate_hz", number(config.rate_hz) + " is outside 1..10000 Hz");
  if (!(config.jitter_stddev >= 0.0) || !std::isfinite(config.jitter_stddev))
    fail("jitter_stddev", number(config.jitter_stddev) + " is not a finite value >= 0");
  if (!(config.dropout_probability >= 0.0 && config.dropout_probability <= 1.0))
    fail("dropout_probability", number(config.dropout_probability) + " is outside [0, 1]");
  // Script times become int64 microseconds of device time and nanoseconds of delivery time:
  // past a year (an hour of latency) they are typos, and far past it they overflow.
  if (!(config.latency_ms >= 0.0 && config.latency_ms <= base::kMaxTimeoutMs))
    fail("latency_ms", number(config.latency_ms) + " ms is outside [0, " + number(base::kMaxTimeoutMs) + "] (an hour)");
  if (!(config.duration_s >= 0.0 && config.duration_s <= base::kMaxDurationS))
    fail("duration_s", number(config.duration_s) + " s is outside [0, " + number(base::kMaxDurationS) + "] (a year)");

  for (auto& hand : script_of_) hand.fill(kUnscripted);
  scripts_.reserve(config.fingers.size());
  for (std::size_t i = 0; i < config.fingers.size(); ++i) {
    const FingerScript& f = config.fingers[i];
    const std::string field = finger_field(i);
    if (f.hand >= kHands) fail(field + ".hand", std::to_string(f.hand) + " is not 0..1");
    if (f.finger >= kFingers) fail(field + ".finger", std::to_string(f.finger) + " is not 0..4");
    if (f.keyframes.empty()) fail(field + ".keyframes", "no keyframes");
    for (std::size_t k = 0; k < f.keyframes.size(); ++k) {
      const Keyframe& key = f.keyframes[k];
      const std::string kf = field + ".keyframes[" + std::to_string(k) + "]";
      if (!(key.time_s >= 0.0 && key.time_s <= base::kMaxDurationS))
        fail(kf, "time " + number(key.time_s) + " s is outside [0, " + number(base::kMaxDurationS) + "] (a year)");
      if (!std::isfinite(key.x) || !std::isfinite(key.y) || !std::isfinite(key.z)) fail(kf, "position is not finite");
      // Equal times are allowed: they make an instant step, e.g. a finger placed on contact.
      if (k > 0 && key.time_s < f.keyframes[k - 1].time_s)
        fail(kf,
             "time goes backwards (" + number(key.time_s) + " s after " + number(f.keyframes[k - 1].time_s) + " s)");
    }
    int& slot = script_of_[f.hand][f.finger];
    if (slot != kUnscripted)
      fail(field, "hand " + std::to_string(f.hand) + " finger " + std::to_string(f.finger) +
                      " is already scripted by finger[" + std::to_string(slot) + "]");
    slot = static_cast<int>(i);
    scripts_.push_back(f.keyframes);
    active_[f.hand] = true;
    loop_period_s_ = std::max(loop_period_s_, f.keyframes.back().time_s);
  }
  if (config.duration_s > 0.0)
    end_time_s_ = config.duration_s;
  else if (repeat_ && loop_period_s_ > 0.0)
    end_time_s_ = std::numeric_limits<double>::infinity();
  else
    end_time_s_ = loop_period_s_;
  // next() skips dropped samples in a loop; an endless script that drops everything would
  // never return.
  if (config.dropout_probability >= 1.0 && std::isinf(end_time_s_))
    fail("dropout_probability", "1 with an endless repeating script would never send a sample");
}

void SimScript::reset() noexcept {
  rng_.seed(seed_);
  normal_.reset();
  uniform_.reset();
  tick_ = 0;
  hand_cursor_ = 0;
  sequence_.fill(0);
  generated_ = 0;
  dropped_ = 0;
}

Point3f SimScript::interpolate(const std::vector<Keyframe>& keys, double t_s) const noexcept {
  if (repeat_ && loop_period_s_ > 0.0) t_s = std::fmod(t_s, loop_period_s_);
  const Keyframe* chosen = nullptr;
  if (t_s <= keys.front().time_s) {
    chosen = &keys.front();
  } else if (t_s >= keys.back().time_s) {
    chosen = &keys.back();
  }
  if (chosen != nullptr)
    return {static_cast<float>(chosen->x), static_cast<float>(chosen->y), static_cast<float>(chosen->z)};
  // First keyframe strictly after t; the one before it is at or before t.
  const auto after =
      std::upper_bound(keys.begin(), keys.end(), t_s, [](double t, const Keyframe& k) { return t < k.time_s; });
  const Keyframe& b = *after;
  const Keyframe& a = *(after - 1);
  const double span = b.time_s - a.time_s;  // > 0: a.time <= t < b.time
  const double w = (t_s - a.time_s) / span;
  return {static_cast<float>(a.x + w * (b.x - a.x)), static_cast<float>(a.y + w * (b.y - a.y)),
          static_cast<float>(a.z + w * (b.z - a.z))};
}

bool SimScript::scripted_tip(std::uint8_t hand, std::uint8_t finger, double t_s, Point3f& out) const noexcept {
  if (hand >= kHands || finger >= kFingers) return false;
  const int s = script_of_[hand][finger];
  if (s == kUnscripted) return false;
  out = interpolate(scripts_[static_cast<std::size_t>(s)], t_s);
  return true;
}

void SimScript::fill(std::uint8_t hand, double t_s, GloveSample& out) noexcept {
  out = GloveSample{};
  out.hand = hand;
  out.kind = SampleKind::kPositions;
  for (std::size_t f = 0; f < kFingers; ++f) {
    const int s = script_of_[hand][f];
    Point3f tip;
    if (s == kUnscripted) {
      tip = kSimRestTip;
      tip[0] += kSimJointSpacing * static_cast<float>(f);
    } else {
      tip = interpolate(scripts_[static_cast<std::size_t>(s)], t_s);
      if (jitter_stddev_ > 0.0) {
        for (float& c : tip) c += static_cast<float>(jitter_stddev_ * normal_(rng_));
      }
    }
    place_finger(f, tip, out);
  }
}

bool SimScript::next(GloveSample& out) noexcept {
  for (;;) {
    if (hand_cursor_ >= kHands) {
      hand_cursor_ = 0;
      ++tick_;
    }
    if (!active_[0] && !active_[1]) return false;
    const double t_s = static_cast<double>(tick_) / rate_hz_;
    // A small tolerance so a keyframe time that is a whole number of ticks is reached despite
    // rounding in tick / rate.
    if (t_s > end_time_s_ + 1e-9) return false;
    const auto hand = static_cast<std::uint8_t>(hand_cursor_++);
    if (!active_[hand]) continue;

    const std::uint32_t sequence = sequence_[hand]++;
    ++generated_;
    if (dropout_probability_ > 0.0 && uniform_(rng_) < dropout_probability_) {
      ++dropped_;
      continue;
    }
    fill(hand, t_s, out);
    out.sequence = sequence;
    out.device_time_us = static_cast<std::uint64_t>(std::llround(static_cast<double>(tick_) * 1e6 / rate_hz_));
    return true;
  }
}

}  // namespace sculpt::hal
