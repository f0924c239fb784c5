#include "lcm_receiver.hpp"

#include <lcm/lcm-cpp.hpp>

#include <stdexcept>

#include "sculpt/hal/lcm_handle.hpp"
#include "sculpt/logging/channels.hpp"
#include "sculpt_lcm/collision_event_t.hpp"
#include "sculpt_lcm/fingertip_state_t.hpp"
#include "sculpt_lcm/tick_stats_t.hpp"

namespace sculpt::view {
namespace {

// How long one handleTimeout waits: only the latency of stopping.
constexpr int kHandleTimeoutMs = 50;

}  // namespace

LcmReceiver::LcmReceiver(const std::string& url) : lcm_(std::make_unique<lcm::LCM>(url)) {
  if (!lcm_->good()) throw std::runtime_error("cannot start LCM on '" + url + "'");
  if (!hal::lcm_has_socket(*lcm_)) throw std::runtime_error("no LCM server answered at '" + url + "'");
  lcm_->subscribeFunction<sculpt_lcm::collision_event_t, LcmReceiver*>(
      logging::kCollisionChannel,
      [](const lcm::ReceiveBuffer*, const std::string&, const sculpt_lcm::collision_event_t* m, LcmReceiver* self) {
        logging::CollisionRecord record;
        if (logging::from_lcm(*m, record)) {
          self->push(record);
        } else {
          ++self->undecodable_;
        }
      },
      this);
  lcm_->subscribeFunction<sculpt_lcm::fingertip_state_t, LcmReceiver*>(
      logging::kFingertipChannel,
      [](const lcm::ReceiveBuffer*, const std::string&, const sculpt_lcm::fingertip_state_t* m, LcmReceiver* self) {
        self->push(FingertipSeen{
            m->tick, m->hand, m->finger, {m->registered[0], m->registered[1], m->registered[2]}, m->in_contact != 0});
      },
      this);
  lcm_->subscribeFunction<sculpt_lcm::tick_stats_t, LcmReceiver*>(
      logging::kTickChannel,
      [](const lcm::ReceiveBuffer*, const std::string&, const sculpt_lcm::tick_stats_t* m, LcmReceiver* self) {
        self->push(TickSeen{m->tick, m->collisions, m->tick_time_us, m->budget_us, m->overruns});
      },
      this);
  thread_ = std::thread([this] { receive(); });
}

LcmReceiver::~LcmReceiver() {
  stop_ = true;
  thread_.join();
}

void LcmReceiver::receive() {
  while (!stop_) {
    if (hal::lcm_handle_within(*lcm_, kHandleTimeoutMs) < 0) return;
  }
}

void LcmReceiver::push(LiveMessage message) {
  const std::lock_guard lock(mutex_);
  queue_.push_back(std::move(message));
}

std::vector<LiveMessage> LcmReceiver::take() {
  std::vector<LiveMessage> out;
  const std::lock_guard lock(mutex_);
  out.swap(queue_);
  return out;
}

}  // namespace sculpt::view
