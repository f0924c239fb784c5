#pragma once
// The station's live channels, received on a thread of the viewer's own: rendering a frame
// takes tens of milliseconds, and a socket left unread that long at 1 kHz of tick statistics
// overflows and drops exactly the collision events the copy needs.

#include <atomic>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <variant>
#include <vector>

#include "sculpt/logging/records.hpp"
#include "view_state.hpp"

namespace lcm {
class LCM;
class Subscription;
}  // namespace lcm

namespace sculpt::view {

using LiveMessage = std::variant<logging::CollisionRecord, FingertipSeen, TickSeen>;

class LcmReceiver {
 public:
  /// Subscribes to SCULPT_COLLISION, SCULPT_FINGERTIP and SCULPT_TICK on `url` and starts
  /// receiving. @throw std::runtime_error when LCM cannot be started on `url`, or when it is a
  /// tcpq URL whose server does not answer. A tcpq server that goes away is listened to again
  /// once it answers (looked for every second).
  explicit LcmReceiver(const std::string& url);
  ~LcmReceiver();
  LcmReceiver(const LcmReceiver&) = delete;
  LcmReceiver& operator=(const LcmReceiver&) = delete;

  /// Everything received since the last call, in arrival order.
  std::vector<LiveMessage> take();
  /// Collision events that did not decode (counted, not shown).
  std::size_t undecodable() const { return undecodable_.load(); }
  /// New instances made after a tcpq server went away and answered again.
  std::size_t reconnects() const { return reconnects_.load(); }

 private:
  std::vector<lcm::Subscription*> subscribe(lcm::LCM& lcm);
  bool reconnect();
  void receive();
  void push(LiveMessage message);

  std::string url_;                // the URL lcm_ was made on (a tcpq host by its address: hal::open_lcm)
  std::unique_ptr<lcm::LCM> lcm_;  // the receiving thread's once it runs, as are its subscriptions
  std::vector<lcm::Subscription*> subscriptions_;
  std::mutex mutex_;
  std::vector<LiveMessage> queue_;
  std::atomic<bool> stop_{false};
  std::atomic<std::size_t> undecodable_{0};
  std::atomic<std::size_t> reconnects_{0};
  std::thread thread_;
};

}  // namespace sculpt::view
