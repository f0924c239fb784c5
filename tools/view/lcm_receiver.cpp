#include "lcm_receiver.hpp"

#include <lcm/lcm-cpp.hpp>

#include <chrono>
#include <stdexcept>
#include <utility>

#include "sculpt/hal/lcm_handle.hpp"
#include "sculpt/hal/tcpq_probe.hpp"
#include "sculpt/logging/channels.hpp"
#include "sculpt_lcm/collision_event_t.hpp"
#include "sculpt_lcm/fingertip_state_t.hpp"
#include "sculpt_lcm/tick_stats_t.hpp"

namespace sculpt::view {
namespace {

// How long one handleTimeout waits: only the latency of stopping.
constexpr int kHandleTimeoutMs = 50;
// Back-off while LCM reports errors, so a broken socket does not spin a core.
constexpr std::chrono::milliseconds kErrorBackoff{50};

}  // namespace

LcmReceiver::LcmReceiver(const std::string& url) {
  hal::OpenedLcm opened = hal::open_lcm(url, "LCM viewer");
  lcm_ = std::move(opened.instance);
  url_ = std::move(opened.url);
  subscriptions_ = subscribe(*lcm_);
  thread_ = std::thread([this] { receive(); });
}

LcmReceiver::~LcmReceiver() {
  stop_ = true;
  thread_.join();
  hal::destroy_without_waiting(std::move(lcm_), url_, std::move(subscriptions_));
}

std::vector<lcm::Subscription*> LcmReceiver::subscribe(lcm::LCM& lcm) {
  std::vector<lcm::Subscription*> made;
  made.push_back(lcm.subscribeFunction<sculpt_lcm::collision_event_t, LcmReceiver*>(
      logging::kCollisionChannel,
      [](const lcm::ReceiveBuffer*, const std::string&, const sculpt_lcm::collision_event_t* m, LcmReceiver* self) {
        logging::CollisionRecord record;
        if (logging::from_lcm(*m, record)) {
          self->push(record);
        } else {
          ++self->undecodable_;
        }
      },
      this));
  made.push_back(lcm.subscribeFunction<sculpt_lcm::fingertip_state_t, LcmReceiver*>(
      logging::kFingertipChannel,
      [](const lcm::ReceiveBuffer*, const std::string&, const sculpt_lcm::fingertip_state_t* m, LcmReceiver* self) {
        self->push(FingertipSeen{
            m->tick, m->hand, m->finger, {m->registered[0], m->registered[1], m->registered[2]}, m->in_contact != 0});
      },
      this));
  made.push_back(lcm.subscribeFunction<sculpt_lcm::tick_stats_t, LcmReceiver*>(
      logging::kTickChannel,
      [](const lcm::ReceiveBuffer*, const std::string&, const sculpt_lcm::tick_stats_t* m, LcmReceiver* self) {
        self->push(TickSeen{m->tick, m->collisions, m->tick_time_us, m->budget_us, m->overruns});
      },
      this));
  return made;
}

// A tcpq instance whose server went away has no socket and would never deliver again: once the
// server answers a look, a new instance takes its place (the old one goes without waiting on the
// server). What was sent meanwhile is missed, as a burst dropped by UDP is: the viewer's copy
// finds the gap in the collisions' numbers and catches up from the durable log or says it
// diverged.
bool LcmReceiver::reconnect() {
  std::unique_ptr<lcm::LCM> fresh = hal::reopen_lcm(url_);
  if (!fresh) return false;
  std::vector<lcm::Subscription*> made = subscribe(*fresh);
  std::swap(lcm_, fresh);
  std::swap(subscriptions_, made);
  hal::destroy_without_waiting(std::move(fresh), url_, std::move(made));
  ++reconnects_;
  return true;
}

void LcmReceiver::receive() {
  auto next_look = std::chrono::steady_clock::now();
  while (!stop_) {
    if (hal::lcm_handle_within(*lcm_, kHandleTimeoutMs) >= 0) continue;
    if (!hal::lcm_has_socket(*lcm_) && std::chrono::steady_clock::now() >= next_look) {
      next_look = std::chrono::steady_clock::now() + hal::kTcpqLookPeriod;
      try {
        if (reconnect()) continue;
      } catch (const std::exception&) {  // the new instance's allocations: try again at the next look
      }
    }
    std::this_thread::sleep_for(kErrorBackoff);
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
