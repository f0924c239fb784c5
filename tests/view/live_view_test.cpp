// sculpt view as a user runs it, beside a station publishing on a private LCM port, on a private
// Xvfb: its copy of the model is the station's output, its window shows the dent, its keys play a
// recorded session, and the station's ticks are no slower with it attached.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "render/pinhole.hpp"
#include "render/png_reader.cpp"  // stb_image compiled once per test binary, as in render_tests
#include "sculpt/deform/model_io.hpp"
#include "session_log.hpp"
#include "view/view_session.hpp"

namespace sculpt::test {
namespace {

using namespace std::chrono_literals;

// The k-th camera the viewer printed ("view: camera eye X Y Z target X Y Z up X Y Z fov F size
// WxH"): the first when its window opened, one more for each camera key.
render::Camera printed_camera(const std::string& output, std::size_t k = 0) {
  const std::vector<std::string> lines = lines_starting(output, "view: camera ");
  render::Camera c;
  if (lines.size() <= k) return c;
  std::istringstream in(lines[k]);
  std::string word;
  char x = 0;
  in >> word >> word >> word >> c.eye.x >> c.eye.y >> c.eye.z >> word >> c.target.x >> c.target.y >> c.target.z >>
      word >> c.up.x >> c.up.y >> c.up.z >> word >> c.vertical_fov_deg >> word >> c.width >> x >> c.height;
  return c;
}

int channel_difference(const render::Image& a, const render::Image& b, int x, int y) {
  int d = 0;
  for (int k = 0; k < 3; ++k) d += std::abs(int(a.at(x, y)[k]) - int(b.at(x, y)[k]));
  return d;
}

class LiveView : public ViewSession {
 protected:
  // The viewer following `url` until it has been idle for a second and a half.
  std::unique_ptr<ChildProcess> start_viewer(const fs::path& scene, const std::string& name,
                                             const std::vector<std::string>& extra = {}) {
    std::vector<std::string> args = {SCULPT_BINARY, "view", scene.string(), "--up", "z", "--exit-after-idle", "1.5"};
    args.insert(args.end(), extra.begin(), extra.end());
    auto viewer = std::make_unique<ChildProcess>(args, (dir_ / name).string());
    EXPECT_TRUE(wait_for_line(dir_ / name, "view: following", 60s)) << read_text(dir_ / name);
    return viewer;
  }
  static void expect_camera_keys(const fs::path& out);
  static void expect_camera_mouse(const fs::path& out);
};

TEST_F(LiveView, TheCopyIsTheStationsModelAndTheScreenshotShowsTheDent) {
  const std::string url = private_url(0);
  const fs::path scene = press_scene("[lcm]\npublish = true\nurl = \"" + url + "\"");
  const fs::path after = dir_ / "after.png", copy = dir_ / "copy.ply";
  std::string exit_line;
  const auto start = std::chrono::steady_clock::now();
  for (int attempt = 0; attempt < 2; ++attempt) {  // UDP may drop a burst: then once more
    auto viewer = start_viewer(scene, "view.txt", {"--screenshot", after.string(), "--dump-model", copy.string()});
    // Once more replaces the first attempt's session (a station refuses to erase a log holding one).
    const std::vector<std::string> replace =
        attempt > 0 ? std::vector<std::string>{"--replace-log"} : std::vector<std::string>{};
    ASSERT_EQ(run_station(scene, 4.0, replace), 0) << read_text(dir_ / "run.txt");
    ASSERT_EQ(viewer->wait(60s), 0) << read_text(dir_ / "view.txt");
    const auto exits = lines_starting(read_text(dir_ / "view.txt"), "view: exit ");
    ASSERT_EQ(exits.size(), 1u) << read_text(dir_ / "view.txt");
    exit_line = exits.front();
    std::printf("[ view ] attempt %d: %s\n", attempt + 1, exit_line.c_str());
    if (exit_line.find(" gaps 0") != std::string::npos) break;
  }
  std::printf("[ view ] live session with the viewer: %.1f s\n",
              std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  ASSERT_NE(exit_line.find(" gaps 0"), std::string::npos) << "both attempts lost frames: " << exit_line;
  EXPECT_EQ(exit_line.find("DIVERGED"), std::string::npos);

  const view::SessionLog log = view::read_session_log((dir_ / "sphere-press.lcmlog").string());
  ASSERT_FALSE(log.collisions.empty());
  EXPECT_TRUE(same_points(deform::read_model(copy.string()), deform::read_model((dir_ / "sphere-press.ply").string())))
      << "the viewer's copy differs from the station's output";

  // The same window at frame 0 of the recording: before the first collision.
  const fs::path before = dir_ / "before.png";
  ChildProcess paused({SCULPT_BINARY, "view", scene.string(), "--up", "z", "--log",
                       (dir_ / "sphere-press.lcmlog").string(), "--paused", "--screenshot", before.string()},
                      (dir_ / "before.txt").string());
  ASSERT_TRUE(wait_for_line(dir_ / "before.txt", "view: frame 0/", 60s)) << read_text(dir_ / "before.txt");
  ASSERT_TRUE(send_keys("q"));
  ASSERT_EQ(paused.wait(30s), 0) << read_text(dir_ / "before.txt");

  const render::Image a = read_png(before.string()), b = read_png(after.string());
  const render::Camera camera = printed_camera(read_text(dir_ / "view.txt"));
  ASSERT_GT(a.width, 0);
  ASSERT_EQ(a.width, b.width);
  ASSERT_EQ(a.height, b.height);
  ASSERT_EQ(camera.width, a.width);
  // Where the deepest contact lands in the picture, by the test's own pinhole maths.
  const logging::CollisionRecord& deepest =
      *std::min_element(log.collisions.begin(), log.collisions.end(),
                        [](const auto& p, const auto& q) { return p.contact[2] < q.contact[2]; });
  const PixelPoint at = project(camera, {deepest.contact[0], deepest.contact[1], deepest.contact[2]});
  int near = 0, near_total = 0, corner = 0;
  constexpr int kRadius = 14;
  for (int y = 0; y < a.height; ++y) {
    for (int x = 0; x < a.width; ++x) {
      const bool changed = channel_difference(a, b, x, y) > 30;
      if (std::hypot(x + 0.5 - at.x, y + 0.5 - at.y) <= kRadius) {
        ++near_total;
        near += changed;
      } else if (x > a.width * 3 / 4 && y > a.height * 3 / 4) {
        corner += changed;  // background, far from the model
      }
    }
  }
  std::printf("[ view ] contact at pixel (%.0f, %.0f): %d of %d pixels within %d px changed, %d in the far corner\n",
              at.x, at.y, near, near_total, kRadius, corner);
  // More than the contact marker's few pixels: the dent's shading and the force arrow.
  EXPECT_GE(near, 60);
  EXPECT_EQ(corner, 0);
}

// d, w, z and r (up is z): an orbit of 15 degrees about the up axis at the same height and
// distance, a tilt of 10 degrees up, a fifth closer along the same line, and the first view
// again, each camera printed as it is placed; the target never moves.
void LiveView::expect_camera_keys(const fs::path& out) {
  ASSERT_TRUE(send_keys("d w z r"));
  const auto end = std::chrono::steady_clock::now() + 20s;
  while (lines_starting(read_text(out), "view: camera ").size() < 5 && std::chrono::steady_clock::now() < end) {
    std::this_thread::sleep_for(50ms);
  }
  const std::string text = read_text(out);
  const std::vector<std::string> lines = lines_starting(text, "view: camera ");
  ASSERT_EQ(lines.size(), 5u) << text;
  EXPECT_EQ(lines[4], lines[0]) << "r returns to the first view";
  std::vector<deform::Vec3> eye;  // from the target
  for (std::size_t k = 0; k < 4; ++k) {
    const render::Camera c = printed_camera(text, k);
    EXPECT_NEAR(deform::norm(c.target - printed_camera(text).target), 0.0, 1e-12);
    eye.push_back(c.eye - c.target);
  }
  const auto azimuth = [](const deform::Vec3& v) { return std::atan2(v.y, v.x) * 180.0 / M_PI; };
  const auto elevation = [](const deform::Vec3& v) { return std::asin(v.z / deform::norm(v)) * 180.0 / M_PI; };
  EXPECT_NEAR(std::abs(std::remainder(azimuth(eye[1]) - azimuth(eye[0]), 360.0)), 15.0, 1e-6);
  EXPECT_NEAR(eye[1].z, eye[0].z, 1e-6 * deform::norm(eye[0]));
  EXPECT_NEAR(deform::norm(eye[1]), deform::norm(eye[0]), 1e-6 * deform::norm(eye[0]));
  EXPECT_NEAR(elevation(eye[2]) - elevation(eye[1]), 10.0, 1e-6);
  EXPECT_NEAR(azimuth(eye[2]), azimuth(eye[1]), 1e-6);
  EXPECT_NEAR(deform::norm(eye[3]) / deform::norm(eye[2]), 0.8, 1e-6);
  EXPECT_NEAR(deform::norm(deform::normalized(eye[3]) - deform::normalized(eye[2])), 0.0, 1e-6);
}

// After the keys (the view back at the first): a left-button drag 80 px right and 30 px up,
// then a wheel notch away from the user. The drag turns the model with the hand, 180 degrees
// a window's width and 90 a height: the camera orbits 22.5 degrees the way a moves it and
// tilts 5.625 down; the notch brings it a fifth closer along the same line.
void LiveView::expect_camera_mouse(const fs::path& out) {
  const std::size_t before = lines_starting(read_text(out), "view: camera ").size();
  ASSERT_GE(before, 1u);
  const render::Camera first = printed_camera(read_text(out), before - 1);
  ASSERT_EQ(first.width, 640);
  ASSERT_EQ(first.height, 480);
  ASSERT_TRUE(send_mouse("mousemove --window %1 200 150 mousedown 1 mousemove --window %1 280 120 mouseup 1 click 4"))
      << "xdotool failed";
  const deform::Vec3 eye0 = first.eye - first.target;
  const auto distance_ratio = [&](const std::string& text) {
    const std::vector<std::string> lines = lines_starting(text, "view: camera ");
    const render::Camera c = printed_camera(text, lines.size() - 1);
    return deform::norm(c.eye - c.target) / deform::norm(eye0);
  };
  const auto end = std::chrono::steady_clock::now() + 20s;
  while (std::abs(distance_ratio(read_text(out)) - 0.8) > 1e-6 && std::chrono::steady_clock::now() < end) {
    std::this_thread::sleep_for(50ms);
  }
  const std::string text = read_text(out);
  const std::vector<std::string> lines = lines_starting(text, "view: camera ");
  // One camera or more: a poll that gathers both moves places the camera once.
  ASSERT_GT(lines.size(), before) << "no camera after the drag and the notch\n" << text;
  const render::Camera last = printed_camera(text, lines.size() - 1);
  const deform::Vec3 eye = last.eye - last.target;
  EXPECT_NEAR(deform::norm(last.target - first.target), 0.0, 1e-12);
  const auto azimuth = [](const deform::Vec3& v) { return std::atan2(v.y, v.x) * 180.0 / M_PI; };
  const auto elevation = [](const deform::Vec3& v) { return std::asin(v.z / deform::norm(v)) * 180.0 / M_PI; };
  EXPECT_NEAR(std::remainder(azimuth(eye) - azimuth(eye0), 360.0), -22.5, 1e-6) << text;
  EXPECT_NEAR(elevation(eye) - elevation(eye0), -5.625, 1e-6) << text;
  EXPECT_NEAR(deform::norm(eye) / deform::norm(eye0), 0.8, 1e-6) << text;
  std::printf("[ view ] drag and wheel: %zu camera lines\n", lines.size() - before);
}

TEST_F(LiveView, KeysPauseStepAndSpeedUpARecordedSession) {
  const fs::path scene = press_scene("");
  ASSERT_EQ(run_station(scene, 4.0), 0) << read_text(dir_ / "run.txt");
  const auto start = std::chrono::steady_clock::now();
  const fs::path out = dir_ / "keys.txt";
  ChildProcess viewer({SCULPT_BINARY, "view", scene.string(), "--up", "z", "--log",
                       (dir_ / "sphere-press.lcmlog").string(), "--paused"},
                      out.string());
  ASSERT_TRUE(wait_for_line(out, "view: frame 0/", 60s)) << read_text(out);
  const std::string total = lines_starting(read_text(out), "view: frame 0/").front().substr(14);
  const std::string frames = total.substr(0, total.find(' '));  // "N" of "frame 0/N"
  ASSERT_GE(std::stoi(frames), 3);
  const auto expect_line = [&](const std::string& line) {
    EXPECT_TRUE(wait_for_line(out, line, 20s)) << "no '" << line << "' in\n" << read_text(out);
  };
  ASSERT_TRUE(send_keys("n"));
  expect_line("view: frame 1/" + frames + " paused speed 1x");
  ASSERT_TRUE(send_keys("Right"));
  expect_line("view: frame 2/" + frames + " paused speed 1x");
  ASSERT_TRUE(send_keys("plus"));
  expect_line("view: frame 2/" + frames + " paused speed 2x");
  expect_camera_keys(out);
  expect_camera_mouse(out);
  ASSERT_TRUE(send_keys("space"));
  expect_line("view: frame 2/" + frames + " playing speed 2x");
  expect_line("view: frame " + frames + "/" + frames + " ended speed 2x");
  ASSERT_TRUE(send_keys("Escape"));
  ASSERT_EQ(viewer.wait(30s), 0) << read_text(out);
  const std::vector<std::string> lines = lines_starting(read_text(out), "view: frame ");
  const std::vector<std::string> expected = {
      "view: frame 0/" + frames + " paused speed 1x",  "view: frame 1/" + frames + " paused speed 1x",
      "view: frame 2/" + frames + " paused speed 1x",  "view: frame 2/" + frames + " paused speed 2x",
      "view: frame 2/" + frames + " playing speed 2x", "view: frame " + frames + "/" + frames + " ended speed 2x"};
  EXPECT_EQ(lines, expected);
  std::printf("[ view ] keys over %s frames: %.1f s\n", frames.c_str(),
              std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
}

TEST_F(LiveView, TheStationsTickP99IsNoWorseWithAViewerAttached) {
  const std::string url = private_url(1);
  const fs::path scene = press_scene("[lcm]\npublish = true\nurl = \"" + url + "\"");
  const auto p99 = [&](const fs::path& json) {
    return nlohmann::json::parse(read_text(json))["tick_time"]["p99_us"].get<double>();
  };
  ASSERT_EQ(run_station(scene, 4.0, {"--json", (dir_ / "alone.json").string()}), 0) << read_text(dir_ / "run.txt");
  auto viewer = start_viewer(scene, "view.txt");
  // The same scene again: its log may replace the first run's (the comparison needs only the JSON).
  ASSERT_EQ(run_station(scene, 4.0, {"--json", (dir_ / "watched.json").string(), "--replace-log"}), 0)
      << read_text(dir_ / "run.txt");
  ASSERT_EQ(viewer->wait(60s), 0) << read_text(dir_ / "view.txt");
  const double alone = p99(dir_ / "alone.json"), watched = p99(dir_ / "watched.json");
  std::printf("[ view ] station tick p99: %.1f us alone, %.1f us with a viewer attached\n", alone, watched);
  const auto exits = lines_starting(read_text(dir_ / "view.txt"), "view: exit ");
  if (!exits.empty()) std::printf("[ view ] %s\n", exits.front().c_str());
  EXPECT_LE(watched, std::max(1.5 * alone, alone + 150.0));
}

TEST_F(LiveView, AViewerStartedLateCatchesUpFromTheLogOrSaysItDiverged) {
  const std::string url = private_url(2);
  const fs::path scene = press_scene("[lcm]\npublish = true\nurl = \"" + url + "\"");
  const fs::path log = dir_ / "sphere-press.lcmlog", caught = dir_ / "caught.ply", blind = dir_ / "blind.ply";
  ChildProcess station({SCULPT_BINARY, "run", scene.string(), "--duration", "4", "--quiet"},
                       (dir_ / "run.txt").string());
  // The station's first ticks go by before either viewer listens: a gap no frame id shows.
  std::this_thread::sleep_for(900ms);  // about when the press begins
  ChildProcess with_log({SCULPT_BINARY, "view", scene.string(), "--up", "z", "--exit-after-idle", "1.5", "--catch-up",
                         log.string(), "--dump-model", caught.string()},
                        (dir_ / "caught.txt").string());
  ChildProcess without(
      {SCULPT_BINARY, "view", scene.string(), "--up", "z", "--exit-after-idle", "1.5", "--dump-model", blind.string()},
      (dir_ / "blind.txt").string());
  ASSERT_EQ(station.wait(), 0) << read_text(dir_ / "run.txt");
  ASSERT_EQ(with_log.wait(60s), 0) << read_text(dir_ / "caught.txt");
  ASSERT_EQ(without.wait(60s), 0) << read_text(dir_ / "blind.txt");
  const auto exit_of = [&](const char* name) {
    const auto lines = lines_starting(read_text(dir_ / name), "view: exit ");
    return lines.empty() ? std::string() : lines.front();
  };
  const std::string caught_exit = exit_of("caught.txt"), blind_exit = exit_of("blind.txt");
  std::printf("[ view ] late with --catch-up: %s\n[ view ] late without: %s\n", caught_exit.c_str(),
              blind_exit.c_str());
  EXPECT_EQ(caught_exit.find("DIVERGED"), std::string::npos) << read_text(dir_ / "caught.txt");
  EXPECT_EQ(caught_exit.find(" gaps 0"), std::string::npos) << "the late start must count as a gap";
  EXPECT_TRUE(
      same_points(deform::read_model(caught.string()), deform::read_model((dir_ / "sphere-press.ply").string())));
  EXPECT_NE(blind_exit.find("DIVERGED by "), std::string::npos) << read_text(dir_ / "blind.txt");
}

}  // namespace
}  // namespace sculpt::test
