// sculpt view's outputs are written when the window closes, maybe after an hour's session, so
// they are checked before it opens: a screenshot not named .png, a model format no writer has,
// and a dump over the scene's base model were found out only at the end, after all the session
// (exit 1, nothing written). Folders still missing are made when the files are written. A
// --catch-up that is a folder is refused at start too.
#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <vector>

#include "sculpt/deform/model_io.hpp"
#include "view/view_session.hpp"

namespace sculpt::test {
namespace {

using namespace std::chrono_literals;

TEST_F(ViewSession, OutputsItCannotWriteAreRefusedBeforeTheWindowOpens) {
  const fs::path scene = this->scene("sphere-press", "");
  ASSERT_EQ(run_station(scene, 1.0), 0) << read_text(dir_ / "run.txt");
  const fs::path log = dir_ / "sphere-press.lcmlog";
  const std::string base = std::string(SCULPT_SOURCE_DIR) + "/data/sphere_3203.ply";
  const std::vector<std::pair<std::vector<std::string>, std::string>> refused = {
      {{"--screenshot", (dir_ / "shot.jpg").string()},
       "--screenshot " + (dir_ / "shot.jpg").string() + ": the picture is written as PNG; name it .png"},
      {{"--dump-model", (dir_ / "copy.obj").string()},
       "--dump-model " + (dir_ / "copy.obj").string() + ": cannot write models with that extension"},
      {{"--dump-model", base}, "--dump-model " + base + " is the scene's model"},
  };
  for (const auto& [options, expected] : refused) {
    std::vector<std::string> args = {SCULPT_BINARY,       "view", scene.string(), "--log", log.string(),
                                     "--exit-after-idle", "0.2"};
    args.insert(args.end(), options.begin(), options.end());
    const fs::path out = dir_ / "refused.txt";
    ChildProcess viewer(args, out.string());
    EXPECT_EQ(viewer.wait(30s), 2) << read_text(out);
    const std::string text = read_text(out);
    EXPECT_NE(text.find("sculpt view: error: " + expected), std::string::npos) << text;
    EXPECT_EQ(text.find("view: frame"), std::string::npos) << "played before refusing: " << text;
  }
  EXPECT_TRUE(fs::exists(base));
  // The catch-up log may not exist yet when the viewer starts, but a folder never becomes one.
  {
    const fs::path out = dir_ / "catch-up.txt";
    ChildProcess viewer({SCULPT_BINARY, "view", scene.string(), "--lcm", private_url(0), "--catch-up", dir_.string(),
                         "--exit-after-idle", "0.2"},
                        out.string());
    EXPECT_EQ(viewer.wait(30s), 2) << read_text(out);
    EXPECT_NE(read_text(out).find("sculpt view: error: --catch-up " + dir_.string() +
                                  ": a directory, not the station's durable log"),
              std::string::npos)
        << read_text(out);
  }
  // Both written at the end, into folders made then.
  const fs::path shot = dir_ / "new" / "deeper" / "shot.png", copy = dir_ / "other" / "copy.ply";
  const fs::path out = dir_ / "view.txt";
  ChildProcess viewer({SCULPT_BINARY, "view", scene.string(), "--log", log.string(), "--exit-after-idle", "0.2",
                       "--screenshot", shot.string(), "--dump-model", copy.string()},
                      out.string());
  ASSERT_EQ(viewer.wait(60s), 0) << read_text(out);
  EXPECT_GT(fs::file_size(shot), 0u);
  EXPECT_TRUE(same_points(deform::read_model(copy.string()), deform::read_model((dir_ / "sphere-press.ply").string())))
      << "the copy is the session's model";
}

}  // namespace
}  // namespace sculpt::test
