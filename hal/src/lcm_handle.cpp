#include "sculpt/hal/lcm_handle.hpp"

#include <lcm/lcm-cpp.hpp>

namespace sculpt::hal {

bool lcm_has_socket(lcm::LCM& lcm) noexcept { return lcm.getFileno() >= 0; }

int lcm_handle_within(lcm::LCM& lcm, int timeout_ms) noexcept {
  if (!lcm_has_socket(lcm)) return -1;
  return lcm.handleTimeout(timeout_ms);
}

}  // namespace sculpt::hal
