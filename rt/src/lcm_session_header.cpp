#include "sculpt/rt/lcm_session_header.hpp"

#include <cmath>
#include <cstdio>

namespace sculpt::rt {

sculpt_lcm::session_header_t to_lcm(const SessionHeader& h, std::int64_t utime) {
  sculpt_lcm::session_header_t m{};
  m.utime = utime;
  m.schema = h.schema;
  m.version = h.version;
  m.scene_path = h.scene_path;
  m.scene_text = h.scene_text;
  m.model_points = static_cast<std::int64_t>(h.model.points);
  m.model_hash = static_cast<std::int64_t>(h.model.hash);
  m.reduced = h.full.has_value();
  m.reduced_ratio = h.full ? h.reduced_ratio : 1.0;
  const deform::ModelIdentity full = h.full.value_or(h.model);
  m.full_points = static_cast<std::int64_t>(full.points);
  m.full_hash = static_cast<std::int64_t>(full.hash);
  return m;
}

bool from_lcm(const sculpt_lcm::session_header_t& m, SessionHeader& out, std::string& error) {
  if (m.schema != kSessionSchema) {
    error = "session header schema " + std::to_string(m.schema) + ", this build reads schema " +
            std::to_string(kSessionSchema);
    return false;
  }
  if (m.model_points < 0 || m.full_points < 0) {
    error = "session header with a negative point count";
    return false;
  }
  if (m.reduced && !(m.reduced_ratio > 0.0 && m.reduced_ratio <= 1.0)) {
    char text[96];
    std::snprintf(text, sizeof text, "session header with reduced_ratio %g (must be in (0, 1])", m.reduced_ratio);
    error = text;
    return false;
  }
  out = {};
  out.schema = m.schema;
  out.version = m.version;
  out.scene_path = m.scene_path;
  out.scene_text = m.scene_text;
  out.model = {static_cast<std::size_t>(m.model_points), static_cast<std::uint64_t>(m.model_hash)};
  if (m.reduced) {
    out.full = deform::ModelIdentity{static_cast<std::size_t>(m.full_points), static_cast<std::uint64_t>(m.full_hash)};
    out.reduced_ratio = m.reduced_ratio;
  }
  return true;
}

}  // namespace sculpt::rt
