#include "sculpt/hal/tcpq_probe.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <charconv>
#include <cstdint>

namespace sculpt::hal {

bool tcpq_server_answers(std::string_view url, int timeout_ms) noexcept {
  constexpr std::string_view kScheme = "tcpq://";
  if (url.substr(0, kScheme.size()) != kScheme) return false;
  std::string_view network = url.substr(kScheme.size());
  network = network.substr(0, network.find('?'));
  if (network.empty()) network = "127.0.0.1:7700";  // liblcm's default
  const std::size_t colon = network.find(':');
  const std::string_view host = network.substr(0, colon);
  int port = 7700;
  if (colon != std::string_view::npos) {
    const std::string_view digits = network.substr(colon + 1);
    const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), port);
    if (error != std::errc() || end != digits.data() + digits.size() || port < 1 || port > 65535) return false;
  }
  std::array<char, 16> text{};  // "255.255.255.255" and its terminator
  if (host.size() >= text.size()) return false;
  host.copy(text.data(), host.size());
  in_addr address{};
  if (::inet_pton(AF_INET, text.data(), &address) != 1) return false;

  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd < 0) return false;
  sockaddr_in server{};
  server.sin_family = AF_INET;
  server.sin_port = htons(static_cast<std::uint16_t>(port));
  server.sin_addr = address;
  bool answered = ::connect(fd, reinterpret_cast<const sockaddr*>(&server), sizeof server) == 0;
  if (!answered && errno == EINPROGRESS) {
    pollfd wait{fd, POLLOUT, 0};
    int error = 0;
    socklen_t length = sizeof error;
    answered =
        ::poll(&wait, 1, timeout_ms) == 1 && ::getsockopt(fd, SOL_SOCKET, SO_ERROR, &error, &length) == 0 && error == 0;
  }
  ::close(fd);
  return answered;
}

}  // namespace sculpt::hal
