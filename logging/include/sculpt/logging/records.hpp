#pragma once
// Plain, fixed-size records the real-time loop hands to the logging thread, one per LCM
// message kind. They are trivially copyable so they cross threads through hal::SpscQueue by
// value; the logging thread turns them into sculpt_lcm messages (to_lcm below).
// Units are those of the matching .lcm field (docs/lcm-types.md).

#include <array>
#include <cstddef>
#include <cstdint>

#include "sculpt/base/clock.hpp"
#include "sculpt/base/vec3.hpp"
#include "sculpt_lcm/collision_event_t.hpp"
#include "sculpt_lcm/fingertip_state_t.hpp"
#include "sculpt_lcm/tick_stats_t.hpp"

namespace sculpt::logging {

using Vec3f = base::Float3;
using Vec3d = base::Double3;

/// Every sculpt_lcm message is fixed-size and well under this many bytes encoded (the largest,
/// glove_sample_t, is 386 with its fingerprint), so the logging threads encode each into one
/// stack buffer of this size instead of allocating per message.
inline constexpr std::size_t kMaxEncodedSize = 1024;

/// Records are stamped with the host's wall clock (sculpt/base/clock.hpp).
using base::wall_time_us;

/// The latest wall-clock time a log may hold: 1 January 2100, microseconds since the epoch.
inline constexpr std::int64_t kLatestLogTimeUs = 4'102'444'800'000'000;

/// A log's time (`utime`) as the nanoseconds a re-run's clock counts. False for a time before
/// 1970 or after 2100, which no station wrote: an edit or damage, whose nanoseconds would
/// overflow, or stretch a re-run over centuries.
inline bool log_time_ns(std::int64_t utime, std::int64_t& ns) noexcept {
  if (utime < 0 || utime > kLatestLogTimeUs) return false;
  ns = utime * 1000;
  return true;
}

/// One fingertip after filtering and registration (sculpt_lcm::fingertip_state_t).
struct FingertipRecord {
  std::int64_t utime = 0;
  std::int64_t tick = 0;
  std::uint8_t hand = 0;
  std::uint8_t finger = 0;
  Vec3f raw{};         ///< glove frame
  Vec3f filtered{};    ///< glove frame
  Vec3f registered{};  ///< model frame
  bool accepted = false;
  bool in_contact = false;
};

enum class CollisionMode : std::uint8_t { kPush = 0, kPull = 1 };
enum class RegionKind : std::uint8_t { kGlobal = 0, kRadius = 1, kIndexSet = 2 };
enum class KernelKind : std::uint8_t { kKelvin = 0, kRegularized = 1 };
enum class ForceForm : std::uint8_t { kScale = 0, kForce = 1 };

/// One finger's collision in one frame: enough to re-apply it without collision detection
/// (sculpt_lcm::collision_event_t).
struct CollisionRecord {
  std::int64_t utime = 0;
  std::int64_t tick = 0;
  double time_s = 0.0;
  std::uint8_t hand = 0;
  std::uint8_t finger = 0;
  CollisionMode mode = CollisionMode::kPush;
  Vec3d probe{};
  std::int32_t contact_index = -1;
  Vec3d contact{};
  Vec3d source{};
  Vec3d force{};  ///< F = P_f - A
  Vec3d weights{};
  Vec3d effective_force{};
  double bc_radius = 0.0;
  RegionKind region_kind = RegionKind::kGlobal;
  Vec3d region_centre{};
  double region_radius = 0.0;
  std::int32_t region_id = -1;
  KernelKind kernel = KernelKind::kKelvin;
  double kernel_eps = 0.0;
  double shear_modulus = 0.0;
  double poisson_ratio = 0.0;
  ForceForm form = ForceForm::kScale;
  double residual = 0.0;
  double condition = 0.0;
  std::int64_t frame_id = 0;             ///< shared by the events of one jointly solved frame
  std::uint8_t frame_size = 1;           ///< how many events that frame has
  double min_jacobian = 1.0;             ///< smallest det(I + grad u) the frame left
  double miss = 0.0;                     ///< probe depth across the surface after the solve
  std::array<std::int32_t, 8> guards{};  ///< per stability guard, in deform::for_each_guard order
};

/// One tick's accounting (sculpt_lcm::tick_stats_t).
struct TickRecord {
  std::int64_t utime = 0;
  std::int64_t tick = 0;
  float tick_time_us = 0.0f;
  float budget_us = 0.0f;
  std::int64_t overruns = 0;
  std::int64_t missed_periods = 0;
  std::int32_t region_points = 0;
  std::int16_t collisions = 0;
  std::int8_t glove_state = 0;  ///< sculpt_lcm::tick_stats_t::GLOVE_*
  float glove_age_ms = 0.0f;
  float min_jacobian = 1.0f;
  std::int32_t guards_acted = 0;
  std::int64_t out_of_range = 0;
};

void to_lcm(const FingertipRecord& record, sculpt_lcm::fingertip_state_t& out) noexcept;
void to_lcm(const CollisionRecord& record, sculpt_lcm::collision_event_t& out) noexcept;
void to_lcm(const TickRecord& record, sculpt_lcm::tick_stats_t& out) noexcept;

/// Reads a collision event back for replay. False (no throw) when an enum is out of range,
/// hand/finger are out of range, frame_size < 1, or a position, force, weight or material
/// value is not finite (residual and condition may be infinite: a rank-deficient solve).
bool from_lcm(const sculpt_lcm::collision_event_t& message, CollisionRecord& out) noexcept;

}  // namespace sculpt::logging
