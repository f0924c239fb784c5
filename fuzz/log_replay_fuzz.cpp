// libFuzzer target: any bytes as a session log, read the way sculpt replay reads one: every
// event past damage (for_each_event), each station message decoded, and the collisions
// transferred onto a small sphere. Damage is reported at an offset inside the file and named
// by its path; nothing throws out of the walk; the model ends finite, and a log whose
// structure transfer() refuses leaves it as it was.

#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "sculpt/deform/generators.hpp"
#include "sculpt/logging/channels.hpp"
#include "sculpt/logging/event_log_reader.hpp"
#include "sculpt/logging/event_log_walk.hpp"
#include "sculpt/logging/records.hpp"
#include "sculpt/rt/lcm_session_header.hpp"
#include "sculpt/rt/log_edit.hpp"
#include "sculpt/rt/transfer.hpp"
#include "sculpt_lcm/fingertip_state_t.hpp"
#include "sculpt_lcm/tick_stats_t.hpp"

namespace {

[[noreturn]] void fail(const std::string& what) {
  std::fprintf(stderr, "log_replay_fuzz: %s\n", what.c_str());
  std::abort();
}

const std::string& log_path() {
  static const std::string path =
      (std::filesystem::temp_directory_path() / ("sculpt_log_fuzz_" + std::to_string(getpid()) + ".lcmlog")).string();
  return path;
}

bool all_finite(const sculpt::deform::PointModel& m) {
  for (std::size_t i = 0; i < m.size(); ++i) {
    if (!std::isfinite(m.x[i]) || !std::isfinite(m.y[i]) || !std::isfinite(m.z[i])) return false;
    if (m.has_normals() && (!std::isfinite(m.nx[i]) || !std::isfinite(m.ny[i]) || !std::isfinite(m.nz[i]))) {
      return false;
    }
  }
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace sculpt;
  const std::string& path = log_path();
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr || std::fwrite(data, 1, size, file) != size || std::fclose(file) != 0)
    fail("cannot write " + path);

  std::vector<logging::CollisionRecord> collisions;
  logging::for_each_event(
      path,
      [&](const logging::LogEvent& event) {
        std::string error;
        if (event.channel == logging::kCollisionChannel) {
          sculpt_lcm::collision_event_t message;
          logging::CollisionRecord record;
          if (logging::decode(event, message, error) && logging::from_lcm(message, record))
            collisions.push_back(record);
        } else if (event.channel == logging::kSessionChannel) {
          sculpt_lcm::session_header_t message;
          rt::SessionHeader header;
          if (logging::decode(event, message, error)) (void)rt::from_lcm(message, header, error);
        } else if (event.channel == logging::kTickChannel) {
          sculpt_lcm::tick_stats_t message;
          (void)logging::decode(event, message, error);
        } else if (event.channel == logging::kFingertipChannel) {
          sculpt_lcm::fingertip_state_t message;
          (void)logging::decode(event, message, error);
        }
      },
      [&](std::uint64_t offset, const std::string& what) {
        if (offset > size) fail("damage at offset " + std::to_string(offset) + " past the end: " + what);
        if (what.rfind(path, 0) != 0) fail("damage not named by the log's path: " + what);
      });

  static const deform::PointModel kBase = deform::make_sphere(300);
  deform::PointModel model = kBase;
  try {
    rt::transfer(model, rt::drop_incomplete_frames(collisions), {}, {}, [](const rt::FrameRejected&) { return true; });
  } catch (const rt::FrameRejected&) {
    if (model.x != kBase.x || model.y != kBase.y || model.z != kBase.z) fail("a refused log moved the model");
  }
  if (!all_finite(model)) fail("a non-finite position or normal after the transfer");
  return 0;
}
