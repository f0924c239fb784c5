#pragma once
// LCM channel names of the station. Scenes may rename the glove and haptic channels
// (hal::LcmConfig); these are the defaults and the names every tool expects.

namespace sculpt::logging {

/// The session header, the first event of every durable log (sculpt_lcm::session_header_t).
inline constexpr const char* kSessionChannel = "SCULPT_SESSION";
inline constexpr const char* kGloveChannel = "SCULPT_GLOVE";          ///< sculpt_lcm::glove_sample_t
inline constexpr const char* kFingertipChannel = "SCULPT_FINGERTIP";  ///< sculpt_lcm::fingertip_state_t
inline constexpr const char* kCollisionChannel = "SCULPT_COLLISION";  ///< sculpt_lcm::collision_event_t
inline constexpr const char* kTickChannel = "SCULPT_TICK";            ///< sculpt_lcm::tick_stats_t
inline constexpr const char* kHapticChannel = "SCULPT_HAPTIC";        ///< sculpt_lcm::haptic_command_t
/// The durable log's own checks of its events (sculpt_lcm::log_check_t, event_check.hpp); never
/// published live, and consumed by the walk (event_log_walk.hpp) rather than handed on.
inline constexpr const char* kCheckChannel = "SCULPT_CHECK";

}  // namespace sculpt::logging
