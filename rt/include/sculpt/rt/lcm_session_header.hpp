#pragma once
// The session header on the wire (sculpt_lcm::session_header_t, channel SCULPT_SESSION).
// Only with LCM.

#include <cstdint>
#include <string>

#include "sculpt/rt/session_header.hpp"
#include "sculpt_lcm/session_header_t.hpp"

namespace sculpt::rt {

sculpt_lcm::session_header_t to_lcm(const SessionHeader& header, std::int64_t utime);

/// False, with `error` saying why, for a schema this build does not know, negative counts or a
/// ratio outside (0, 1].
bool from_lcm(const sculpt_lcm::session_header_t& message, SessionHeader& out, std::string& error);

}  // namespace sculpt::rt
