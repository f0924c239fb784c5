#include "sculpt/hal/lcm_handle.hpp"

#include <lcm/lcm-cpp.hpp>

#include <atomic>
#include <optional>
#include <stdexcept>
#include <thread>

#include "sculpt/hal/tcpq_probe.hpp"

namespace sculpt::hal {
namespace {

std::atomic<std::size_t> in_flight{0};  // destroy_without_waiting's threads still running

}  // namespace

OpenedLcm open_lcm(const std::string& url, std::string_view who) {
  const auto failure = [&](std::string_view what) {
    return std::runtime_error(std::string(who) + ": " + std::string(what) + " '" + url + "'");
  };
  std::optional<std::string> by_address = tcpq_url_by_address(url);
  if (!by_address) throw failure("no address for the host in");
  if (tcpq_server_address(*by_address) && !tcpq_server_answers(*by_address, kTcpqLookTimeoutMs)) {
    throw failure("no server answered at");
  }
  auto made = std::make_unique<lcm::LCM>(*by_address);
  if (!made->good()) throw failure("cannot open LCM at");
  // A tcpq instance whose server went between the look and the connect has no socket, and
  // would never deliver.
  if (!lcm_has_socket(*made)) throw failure("no server answered at");
  return {std::move(made), std::move(*by_address)};
}

std::unique_ptr<lcm::LCM> reopen_lcm(const std::string& url) noexcept {
  if (!tcpq_server_answers(url, kTcpqLookTimeoutMs)) return nullptr;
  try {
    auto made = std::make_unique<lcm::LCM>(url);
    if (made->good() && lcm_has_socket(*made)) return made;
  } catch (...) {  // the instance's allocations: nothing, looked for again later
  }
  return nullptr;
}

bool lcm_has_socket(lcm::LCM& lcm) noexcept { return lcm.getFileno() >= 0; }

int lcm_handle_within(lcm::LCM& lcm, int timeout_ms) noexcept {
  if (!lcm_has_socket(lcm)) return -1;
  return lcm.handleTimeout(timeout_ms);
}

void destroy_without_waiting(std::unique_ptr<lcm::LCM> instance, std::string_view url,
                             std::vector<lcm::Subscription*> subscriptions) noexcept {
  if (!instance) return;
  // Each subscription is undone before the instance goes: liblcm 1.3's destroy undoes them by
  // walking its handler list while removing from it, and misses every other one (a tcpq
  // instance then leaks that channel's name, which the leak checker finds).
  const auto destroy = [](lcm::LCM* doomed, const std::vector<lcm::Subscription*>& listed) {
    for (lcm::Subscription* subscription : listed) {
      if (subscription != nullptr) doomed->unsubscribe(subscription);
    }
    delete doomed;
  };
  // Only a tcpq instance connects while it is destroyed: any other goes here and now (a log
  // file's provider, say, which must be closed before the program ends).
  lcm::LCM* const doomed = instance.release();
  if (!is_tcpq_url(url) || lcm_has_socket(*doomed) || tcpq_server_answers(url, kTcpqLookTimeoutMs)) {
    destroy(doomed, subscriptions);
    return;
  }
  in_flight.fetch_add(1, std::memory_order_relaxed);
  try {
    std::thread([doomed, listed = std::move(subscriptions), destroy] {
      destroy(doomed, listed);
      in_flight.fetch_sub(1, std::memory_order_release);
    }).detach();
  } catch (...) {  // std::system_error: the instance stays
    in_flight.fetch_sub(1, std::memory_order_relaxed);
  }
}

std::size_t lcm_destroys_in_flight() noexcept { return in_flight.load(std::memory_order_acquire); }

}  // namespace sculpt::hal
