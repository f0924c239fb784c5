#pragma once
// What the station's tests share: a glove fed by hand, and one finger's press settings.

#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

#include "sculpt/hal/glove_source.hpp"
#include "sculpt/rt/station.hpp"
#include "support/nanoseconds.hpp"

namespace sculpt::rt::test_fixtures {

// A glove the test feeds by hand; poll() hands over what was fed, like a real backend's queue.
class FakeGlove final : public hal::GloveSource {
 public:
  FakeGlove() { pending_.resize(64); }
  void start() override {}
  void stop() override {}
  std::size_t poll(std::span<hal::GloveSample> out) noexcept override {
    const std::size_t n = std::min(out.size(), count_);
    for (std::size_t i = 0; i < n; ++i) out[i] = pending_[i];
    count_ = 0;
    return n;
  }
  hal::SourceCounters counters() const noexcept override { return {}; }
  hal::SourceState state() const noexcept override { return hal::SourceState::kConnected; }
  const char* name() const noexcept override { return "fake"; }

  void feed(const deform::Vec3& index_tip, std::int64_t now_ns, std::uint64_t device_us, std::uint8_t hand = 0) {
    hal::GloveSample s;
    s.hand = hand;
    s.device_time_us = device_us;
    s.receive_time_ns = now_ns;
    s.joints[hal::kTipJoint[1]] = {static_cast<float>(index_tip.x), static_cast<float>(index_tip.y),
                                   static_cast<float>(index_tip.z)};
    feed_sample(s);
  }

  /// A sample as a backend would hand it over, stamped with the next sequence number.
  void feed_sample(hal::GloveSample s) {
    s.sequence = sequence_++;
    pending_[count_++] = s;
  }

 private:
  std::vector<hal::GloveSample> pending_;
  std::size_t count_ = 0;
  std::uint32_t sequence_ = 0;
};

/// One index finger (hand 0) pressing a unit sphere: exact positions, no filter.
inline StationSettings press_settings() {
  StationSettings s;
  s.fingers = {{0, 1}};
  s.filter_enabled = false;  // the test drives exact positions
  s.delta_s = 0.02;
  s.glove_timeout_s = 0.05;
  s.region.kind = RegionPolicy::Kind::kAuto;
  s.deform.contact.bc_radius = 0.06;
  s.deform.contact.min_source_distance = 0.01;
  s.deform.contact.guard_distance = 0.05;
  return s;
}

using test::kMs;

}  // namespace sculpt::rt::test_fixtures
