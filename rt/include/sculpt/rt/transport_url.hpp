#pragma once
// An LCM URL and channel name checked where they enter (a scene, a --lcm option), so that a typo is named by its
// key before the session, not reported by LCM's own stderr once the station is built.

#include <cstddef>
#include <string>
#include <string_view>

namespace sculpt::rt {

/// What is wrong with `url` as an LCM 1.3 URL, or empty when nothing is: the form
/// provider://network?key=value&..., a provider LCM has (udpm, mpudpm, tcpq, memq, file), for
/// udpm and mpudpm an IPv4 multicast address (224.0.0.0 to 239.255.255.255) and a port in
/// 1..65535 when given and a ttl in 0..255, and for file a file name. Written here rather than
/// asked of LCM because LCM prints its complaint to stderr and only fails once opened (a
/// pure-syntax check; whether the address can be joined is still LCM's to say).
std::string lcm_url_problem(std::string_view url);

/// LCM's longest channel name (LCM_MAX_CHANNEL_NAME_LENGTH in lcm.h, 1.3).
inline constexpr std::size_t kMaxLcmChannelLength = 63;

/// What is wrong with `channel` as an LCM channel name, or empty when nothing is: it must be
/// non-empty, at most 63 bytes, and hold no NUL (LCM's C API would cut it there). A longer name
/// is not refused by LCM until each publish, which prints to stderr and delivers nothing.
std::string lcm_channel_problem(std::string_view channel);

}  // namespace sculpt::rt
