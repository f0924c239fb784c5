#pragma once
// Whether an LCM tcpq server answers, found without liblcm. liblcm 1.3.1 reconnects a tcpq
// instance only inside its blocking handle() (which then waits for a message, so a reader could
// not be stopped) or by making a new instance, whose connect to a host that has gone from the
// network can block for minutes. A non-blocking connect with a short timeout tells first
// whether a new instance would connect at once.

#include <string_view>

namespace sculpt::hal {

/// True when `url` is a tcpq URL (`tcpq://`, `tcpq://HOST`, `tcpq://HOST:PORT`, liblcm's default
/// 127.0.0.1:7700) whose HOST is an IPv4 address in dotted form and whose server accepts a TCP
/// connection within `timeout_ms`; the connection is closed at once. A host name is not looked
/// up (a lookup can block as long as the connect): false.
bool tcpq_server_answers(std::string_view url, int timeout_ms) noexcept;

}  // namespace sculpt::hal
