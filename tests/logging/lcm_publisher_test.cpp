// The live publisher over memq:// (one LCM instance, shared by the publisher and a raw
// capture, so delivery is deterministic and needs no network).

#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include "sculpt/logging/channels.hpp"
#include "sculpt/logging/lcm_publisher.hpp"

namespace sculpt::logging {
namespace {

struct Capture {
  std::map<std::string, std::vector<std::vector<std::uint8_t>>> by_channel;
  std::size_t total = 0;

  static void on_message(const lcm::ReceiveBuffer* rbuf, const std::string& channel, Capture* self) {
    const auto* bytes = static_cast<const std::uint8_t*>(rbuf->data);
    self->by_channel[channel].emplace_back(bytes, bytes + rbuf->data_size);
    ++self->total;
  }

  /// Handles messages on `lcm` until `count` have arrived or two seconds pass.
  void wait_for(lcm::LCM& lcm, std::size_t count) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(2);
    while (total < count && std::chrono::steady_clock::now() < deadline) lcm.handleTimeout(20);
  }
};

template <typename Message>
Message decode(const std::vector<std::uint8_t>& bytes) {
  Message m{};
  EXPECT_EQ(m.decode(bytes.data(), 0, static_cast<int>(bytes.size())), static_cast<int>(bytes.size()));
  return m;
}

TEST(LcmPublisher, PublishesEachRecordKindOnItsChannel) {
  lcm::LCM lcm("memq://");
  ASSERT_TRUE(lcm.good());
  Capture capture;
  lcm.subscribeFunction(".*", &Capture::on_message, &capture);

  LcmPublisher publisher(lcm, PublisherConfig{});
  publisher.start();
  FingertipRecord tip;
  tip.tick = 7;
  tip.finger = 2;
  tip.registered = {1.5f, -2.5f, 0.25f};
  tip.accepted = true;
  CollisionRecord hit;
  hit.tick = 7;
  hit.contact_index = 99;
  hit.force = {0.0, 0.0, -0.01};
  hit.frame_id = 3;
  hit.frame_size = 1;
  TickRecord tick;
  tick.tick = 7;
  tick.tick_time_us = 250.0f;
  EXPECT_TRUE(publisher.publish(tip));
  EXPECT_TRUE(publisher.publish(hit));
  EXPECT_TRUE(publisher.publish(tick));
  capture.wait_for(lcm, 3);
  publisher.stop();

  ASSERT_EQ(capture.total, 3u);
  ASSERT_EQ(capture.by_channel[kFingertipChannel].size(), 1u);
  ASSERT_EQ(capture.by_channel[kCollisionChannel].size(), 1u);
  ASSERT_EQ(capture.by_channel[kTickChannel].size(), 1u);
  const auto f = decode<sculpt_lcm::fingertip_state_t>(capture.by_channel[kFingertipChannel][0]);
  EXPECT_EQ(f.tick, 7);
  EXPECT_EQ(f.finger, 2);
  EXPECT_EQ(f.registered[1], -2.5f);
  EXPECT_EQ(f.accepted, 1);
  const auto c = decode<sculpt_lcm::collision_event_t>(capture.by_channel[kCollisionChannel][0]);
  EXPECT_EQ(c.contact_index, 99);
  EXPECT_EQ(c.force[2], -0.01);
  EXPECT_EQ(c.frame_id, 3);
  const auto t = decode<sculpt_lcm::tick_stats_t>(capture.by_channel[kTickChannel][0]);
  EXPECT_EQ(t.tick_time_us, 250.0f);

  const PublisherCounters counts = publisher.counters();
  EXPECT_EQ(counts.fingertip.published, 1u);
  EXPECT_EQ(counts.collision.published, 1u);
  EXPECT_EQ(counts.tick.published, 1u);
  EXPECT_EQ(counts.dropped(), 0u);
}

TEST(LcmPublisher, FullQueueIsACountedDropAndStopPublishesTheRest) {
  lcm::LCM lcm("memq://");
  Capture capture;
  lcm.subscribeFunction(kTickChannel, &Capture::on_message, &capture);
  PublisherConfig config;
  config.queue_capacity = 4;
  LcmPublisher publisher(lcm, config);
  // Not started: nothing drains, so the fifth and sixth records find the queue full.
  int accepted = 0;
  for (int i = 0; i < 6; ++i) {
    TickRecord r;
    r.tick = i;
    accepted += publisher.publish(r) ? 1 : 0;
  }
  EXPECT_EQ(accepted, 4);
  EXPECT_EQ(publisher.counters().tick.dropped, 2u);
  publisher.start();
  publisher.stop();  // drains before it returns
  EXPECT_EQ(publisher.counters().tick.published, 4u);
  capture.wait_for(lcm, 4);
  ASSERT_EQ(capture.total, 4u);
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(decode<sculpt_lcm::tick_stats_t>(capture.by_channel[kTickChannel][i]).tick, static_cast<std::int64_t>(i));
  }
}

TEST(LcmPublisher, BadUrlThrowsNamingIt) {
  PublisherConfig config;
  config.url = "nosuchprovider://here";
  LcmPublisher publisher(config);
  try {
    publisher.start();
    FAIL() << "start() should have thrown";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("nosuchprovider://here"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(publisher.running());
  publisher.stop();  // harmless after a failed start
}

}  // namespace
}  // namespace sculpt::logging
