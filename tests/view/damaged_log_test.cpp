// sculpt view --log on a damaged session log: the damage is said, a frame it left short of its
// events is named and not played, and the copy is what `sculpt replay --skip-damage` applies
// (replay's own reader and transfer: an independent path to the same model). Before, the
// viewer said nothing and applied the frame's remaining forces alone, moving its copy where
// the station never went.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "sculpt/deform/model_io.hpp"
#include "view/view_session.hpp"

namespace sculpt::test {
namespace {

using namespace std::chrono_literals;

std::uint32_t big_endian_u32(const std::vector<char>& bytes, std::size_t at) {
  std::uint32_t v = 0;
  for (std::size_t k = 0; k < 4; ++k) v = (v << 8) | static_cast<unsigned char>(bytes[at + k]);
  return v;
}

// The log with the sync word of its `nth` SCULPT_COLLISION event (counting from 1) broken,
// so the reader skips that event as damage. LCM log event: sync (4 bytes), event number (8),
// time (8), channel length (4), data length (4), channel, data.
bool break_collision_event(const fs::path& from, const fs::path& to, int nth) {
  std::ifstream in(from, std::ios::binary);
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  int seen = 0;
  bool broken = false;
  for (std::size_t pos = 0; pos + 28 <= bytes.size();) {
    const std::uint32_t channel = big_endian_u32(bytes, pos + 20), data = big_endian_u32(bytes, pos + 24);
    if (std::string(&bytes[pos + 28], channel) == "SCULPT_COLLISION" && ++seen == nth) {
      bytes[pos] = 0x12;
      broken = true;
    }
    pos += 28 + channel + data;
  }
  std::ofstream(to, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  return broken;
}

TEST_F(ViewSession, ADamagedLogPlaysWhatReplaySkipDamageApplies) {
  // Three fingers squeeze the sphere: frames of two and three events.
  const fs::path scene = this->scene("sphere-squeeze", "");
  ASSERT_EQ(run_station(scene, 4.0), 0) << read_text(dir_ / "run.txt");
  const fs::path log = dir_ / "sphere-squeeze.lcmlog", holed = dir_ / "holed.lcmlog";
  ASSERT_TRUE(break_collision_event(log, holed, 2));
  const fs::path copy = dir_ / "copy.ply", replayed = dir_ / "replayed.ply", out = dir_ / "view.txt";
  ChildProcess viewer({SCULPT_BINARY, "view", scene.string(), "--up", "z", "--log", holed.string(), "--exit-after-idle",
                       "0.5", "--dump-model", copy.string()},
                      out.string());
  ASSERT_EQ(viewer.wait(60s), 0) << read_text(out);
  const std::string base = std::string(SCULPT_SOURCE_DIR) + "/data/sphere_3203.ply";
  ChildProcess replay(
      {SCULPT_BINARY, "replay", holed.string(), "--model", base, "--skip-damage", "--out", replayed.string()},
      (dir_ / "replay.txt").string());
  ASSERT_EQ(replay.wait(60s), 0) << read_text(dir_ / "replay.txt");
  const std::string text = read_text(out);
  EXPECT_EQ(lines_starting(text, "view: " + holed.string() + ": 1 damaged or cut places skipped").size(), 1u) << text;
  const std::vector<std::string> incomplete = lines_starting(text, "view: incomplete frame ");
  ASSERT_EQ(incomplete.size(), 1u) << text;
  EXPECT_NE(incomplete.front().find(" events): not played"), std::string::npos) << text;
  EXPECT_TRUE(same_points(deform::read_model(copy.string()), deform::read_model(replayed.string())));
  // The frame left out mattered: the whole session's model is another.
  EXPECT_FALSE(
      same_points(deform::read_model(copy.string()), deform::read_model((dir_ / "sphere-squeeze.ply").string())));
}

}  // namespace
}  // namespace sculpt::test
