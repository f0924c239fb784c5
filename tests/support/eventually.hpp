#pragma once
// Waiting in a test for what another thread, process or device brings about.

#include <chrono>
#include <functional>
#include <thread>

namespace sculpt::test {

/// Asks `done` every `poll` until it holds or `timeout` has passed, and once more at the
/// deadline; whether it held.
inline bool eventually(const std::function<bool()>& done, std::chrono::milliseconds timeout = std::chrono::seconds(5),
                       std::chrono::milliseconds poll = std::chrono::milliseconds(2)) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < deadline) {
    if (done()) return true;
    std::this_thread::sleep_for(poll);
  }
  return done();
}

}  // namespace sculpt::test
