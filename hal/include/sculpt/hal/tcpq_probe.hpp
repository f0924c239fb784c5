#pragma once
// Whether an LCM tcpq server answers, found without liblcm. liblcm reconnects a tcpq instance
// only inside its blocking handle() (which then waits for a message, so a reader could not be
// stopped), when it publishes, or by making a new instance; each connects and then waits for the
// server's handshake without a timeout, so a host gone from the network holds it for minutes and
// a server process that is stopped or hung holds it for ever. A look with a short timeout tells
// first whether liblcm would get through at once.

#include <netinet/in.h>

#include <chrono>
#include <optional>
#include <string>
#include <string_view>

namespace sculpt::hal {

/// How long one look at a tcpq server may take: a server on the network answers well within it,
/// and a stop() that has to look first stays quick.
inline constexpr int kTcpqLookTimeoutMs = 200;
/// How often a reader or writer whose tcpq server went away looks for it again.
inline constexpr std::chrono::milliseconds kTcpqLookPeriod{1000};

inline constexpr std::string_view kTcpqScheme = "tcpq://";
/// Whether `url` names LCM's tcpq provider (liblcm's instances of any other provider never wait
/// on a server).
constexpr bool is_tcpq_url(std::string_view url) noexcept { return url.substr(0, kTcpqScheme.size()) == kTcpqScheme; }

/// The server a tcpq URL names (`tcpq://`, `tcpq://HOST`, `tcpq://HOST:PORT`, liblcm's default
/// 127.0.0.1:7700) when HOST is an IPv4 address in dotted form; nothing for any other URL. A host
/// name is not looked up here (a lookup can block as long as a connect): nothing; a start gives
/// the URL tcpq_url_by_address() made of it.
std::optional<sockaddr_in> tcpq_server_address(std::string_view url) noexcept;

/// `url` with its tcpq server's host name replaced by the IPv4 address it has now, so that
/// liblcm's connects and the looks (tcpq_server_address) need no lookup later: a URL that names
/// an address, or none, or is not tcpq, comes back as it is; nothing when the host has no IPv4
/// address. The lookup may wait as long as the resolver does: only where a start may wait.
std::optional<std::string> tcpq_url_by_address(const std::string& url);

/// True when the server of `url` (tcpq_server_address) accepts a TCP connection and answers LCM's
/// tcpq handshake, all within `timeout_ms`; the connection is closed at once.
bool tcpq_server_answers(std::string_view url, int timeout_ms) noexcept;

}  // namespace sculpt::hal
