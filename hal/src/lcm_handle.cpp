#include "sculpt/hal/lcm_handle.hpp"

#include <lcm/lcm-cpp.hpp>

#include <thread>

#include "sculpt/hal/tcpq_probe.hpp"

namespace sculpt::hal {

bool lcm_has_socket(lcm::LCM& lcm) noexcept { return lcm.getFileno() >= 0; }

int lcm_handle_within(lcm::LCM& lcm, int timeout_ms) noexcept {
  if (!lcm_has_socket(lcm)) return -1;
  return lcm.handleTimeout(timeout_ms);
}

void destroy_without_waiting(std::unique_ptr<lcm::LCM> instance, std::string_view url) noexcept {
  constexpr int kLookTimeoutMs = 200;
  if (!instance || lcm_has_socket(*instance) || tcpq_server_answers(url, kLookTimeoutMs)) return;  // destroyed here
  lcm::LCM* const doomed = instance.release();
  try {
    std::thread([doomed] { delete doomed; }).detach();
  } catch (...) {  // std::system_error: the instance stays
  }
}

}  // namespace sculpt::hal
