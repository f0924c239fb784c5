#pragma once
// Waiting for LCM messages without liblcm 1.3.1's abort: handleTimeout selects on the instance's
// socket, and the tcpq provider has none (-1) while its server is unreachable or after it hung
// up; FD_SET(-1) then ends the process (glibc's fortified FD_SET: "bit out of range"). A station
// started with a tcpq URL and no server, or whose server went away, died that way.

#include <cstddef>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace lcm {
class LCM;
class Subscription;
}  // namespace lcm

namespace sculpt::hal {

/// An instance made by open_lcm(), and the URL it was made on: the one asked for, with a tcpq
/// server's host name replaced by its address (tcpq_url_by_address), which later looks,
/// reopen_lcm() and destroy_without_waiting() are given.
struct OpenedLcm {
  std::unique_ptr<lcm::LCM> instance;
  std::string url;
};

/// A new instance on `url` with its socket. liblcm's tcpq connect and handshake have no timeout
/// (tcpq_probe.hpp), so a tcpq server must answer a look first; a server named by a host name is
/// looked up once, here. Throws std::runtime_error naming `who` and `url`: "WHO: no address
/// for the host in 'URL'", "WHO: no server answered at 'URL'" (the look, or a tcpq instance left
/// without a socket) or "WHO: cannot open LCM at 'URL'" (liblcm refused the URL).
OpenedLcm open_lcm(const std::string& url, std::string_view who);

/// A new instance on `url` in place of one whose tcpq server went away, made only once the server
/// answers a look and only with its socket; nothing otherwise (a look, at most
/// kTcpqLookTimeoutMs, is all it waits for).
std::unique_ptr<lcm::LCM> reopen_lcm(const std::string& url) noexcept;

/// Whether `lcm` has a socket to wait on (false for a tcpq instance not connected to its server).
bool lcm_has_socket(lcm::LCM& lcm) noexcept;

/// lcm.handleTimeout(timeout_ms), or -1 (as handleTimeout reports an error) when the instance
/// has no socket to wait on. This does not reconnect a tcpq instance: its reader reports it
/// disconnected (the station's glove goes stale), and may make a new one (LcmGloveSource).
int lcm_handle_within(lcm::LCM& lcm, int timeout_ms) noexcept;

/// Destroys `instance`, made on `url`, without waiting on its server. liblcm's destroy
/// unsubscribes, and a tcpq instance with no socket connects to its server to do so and waits
/// for the server's handshake: for minutes when the server's host has gone, for ever when its
/// process is stopped or hung (tcpq_probe.hpp). Unless the server answers a look (kTcpqLookTimeoutMs), such
/// an instance is destroyed on a thread of its own that nobody waits for; when no thread can
/// start, it is kept (a few kilobytes, rather than a stop that never returns).
/// `subscriptions` (made on `instance`) are undone first, where it is destroyed.
void destroy_without_waiting(std::unique_ptr<lcm::LCM> instance, std::string_view url,
                             std::vector<lcm::Subscription*> subscriptions = {}) noexcept;

/// How many instances destroy_without_waiting() handed to a thread of their own are still being
/// destroyed (for tests: a program that ends sooner leaves them unfinished, which is harmless
/// but looks like a leak to the leak checker).
std::size_t lcm_destroys_in_flight() noexcept;

}  // namespace sculpt::hal
