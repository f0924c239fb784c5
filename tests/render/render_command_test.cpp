// sculpt render as a user runs it: the real binary, its exit codes, one-line errors and the
// pictures it writes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <vector>

#include "hil/child_process.hpp"
#include "support/bundled_scene.hpp"
#include "render/png_reader.hpp"
#include "sculpt/deform/generators.hpp"
#include "sculpt/deform/model_io.hpp"

namespace sculpt::test {
namespace {

namespace fs = std::filesystem;

struct CommandResult {
  int status = -1;
  std::string output;
};

class RenderCommand : public ::testing::Test {
 protected:
  void SetUp() override {
    folder_ = fs::temp_directory_path() / ("sculpt_render_cli_" + std::to_string(getpid()) + "_" +
                                           ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(folder_);
    fs::create_directories(folder_);
    sphere_ = path("sphere.ply");
    deform::write_model(sphere_, deform::make_sphere(2000, 1.0));
  }
  void TearDown() override { fs::remove_all(folder_); }

  std::string path(const std::string& name) const { return (folder_ / name).string(); }

  CommandResult run(std::vector<std::string> args) const {
    args.insert(args.begin(), {SCULPT_BINARY, "render"});
    const std::string log = path("output.txt");
    ChildProcess child(args, log);
    CommandResult r;
    r.status = child.wait(std::chrono::seconds(60));
    std::ifstream file(log);
    std::stringstream text;
    text << file.rdbuf();
    r.output = text.str();
    return r;
  }

  static void expect_one_line_error(const CommandResult& r, int status, const std::string& part) {
    EXPECT_EQ(r.status, status) << r.output;
    EXPECT_EQ(r.output.rfind("sculpt render: error: ", 0), 0u) << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    EXPECT_NE(r.output.find(part), std::string::npos) << r.output;
  }

  fs::path folder_;
  std::string sphere_;
};

TEST_F(RenderCommand, WritesAPictureOfTheModel) {
  const std::string out = path("sphere.png");
  const CommandResult r = run({sphere_, "--out", out, "--size", "96x80"});
  ASSERT_EQ(r.status, 0) << r.output;
  const render::Image image = read_png(out);
  ASSERT_EQ(image.width, 96);
  ASSERT_EQ(image.height, 80);
  const std::uint8_t* corner = image.at(0, 0);
  const std::uint8_t* centre = image.at(48, 40);
  EXPECT_NE(std::vector<int>(corner, corner + 3), std::vector<int>(centre, centre + 3))
      << "the sphere is in the middle";
}

// --view is a direction: its length does not count. 1e155 overflowed the length (an empty
// picture) and 1e-170 underflowed it ("the direction is zero"); both now draw what 1,1,1 does.
TEST_F(RenderCommand, AViewDirectionDrawsTheSamePictureAtAnyLength) {
  std::vector<std::string> pictures;
  for (const std::string look : {"1,1,1", "1e155,1e155,1e155", "1e-170,1e-170,1e-170", "4.9e-324,4.9e-324,4.9e-324"}) {
    const std::string out = path("view" + std::to_string(pictures.size()) + ".png");
    const CommandResult r = run({sphere_, "--out", out, "--size", "64x48", "--view", look});
    ASSERT_EQ(r.status, 0) << look << ": " << r.output;
    std::ifstream in(out, std::ios::binary);
    pictures.emplace_back(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  const render::Image image = read_png(path("view0.png"));
  const std::uint8_t* corner = image.at(0, 0);
  const std::uint8_t* centre = image.at(32, 24);
  EXPECT_NE(std::vector<int>(corner, corner + 3), std::vector<int>(centre, centre + 3)) << "the sphere is drawn";
  for (std::size_t i = 1; i < pictures.size(); ++i) EXPECT_EQ(pictures[i], pictures[0]) << "view " << i;
}

TEST_F(RenderCommand, ComparesAndMakesRowsOfViews) {
  deform::PointModel moved = deform::read_model(sphere_);
  moved.set_position(0, moved.position(0) * 0.9);
  const std::string after = path("after.ply");
  deform::write_model(after, moved);
  const CommandResult compare = run({after, "--compare", sphere_, "--out", path("compare.png"), "--size", "64x64"});
  ASSERT_EQ(compare.status, 0) << compare.output;
  EXPECT_NE(compare.output.find("largest displacement 0.1 model units"), std::string::npos) << compare.output;
  EXPECT_GT(read_png(path("compare.png")).width, 128);  // before, after and the colour bar
  const CommandResult views = run({sphere_, "--views", "3", "--out", path("views.png"), "--size", "64x48"});
  ASSERT_EQ(views.status, 0) << views.output;
  const render::Image row = read_png(path("views.png"));
  EXPECT_EQ(row.width, 3 * 64);
  EXPECT_EQ(row.height, 48);
}

// Zero normals are re-estimated as deform and replay do, and said so: lit by them the sphere drew
// as one flat dark disc. The picture then has the sphere's shading: the same brightness as the
// picture with the file's true normals, pixel for pixel within a few levels. Or refused.
TEST_F(RenderCommand, ZeroNormalsAreReestimatedAndDrawnLikeTheTrueOnes) {
  deform::PointModel flat = deform::read_model(sphere_);
  for (std::size_t i = 0; i < flat.size(); ++i) flat.set_normal(i, {0.0, 0.0, 0.0});
  const std::string zero = path("zero.ply");
  deform::write_model(zero, flat);
  const CommandResult truth = run({sphere_, "--out", path("true.png"), "--size", "96x80"});
  ASSERT_EQ(truth.status, 0) << truth.output;
  const CommandResult repaired = run({zero, "--out", path("zero.png"), "--size", "96x80"});
  ASSERT_EQ(repaired.status, 0) << repaired.output;
  EXPECT_NE(repaired.output.find(zero + ": 2,000 zero or non-finite normals re-estimated"), std::string::npos)
      << repaired.output;
  const render::Image a = read_png(path("true.png")), b = read_png(path("zero.png"));
  ASSERT_EQ(a.pixels.size(), b.pixels.size());
  double difference = 0.0, spread = 0.0;
  for (std::size_t i = 0; i < a.pixels.size(); ++i) difference += std::abs(int(a.pixels[i]) - int(b.pixels[i]));
  for (std::size_t i = 0; i < a.pixels.size(); ++i) spread += std::abs(int(a.pixels[i]) - int(a.pixels[0]));
  EXPECT_LT(difference, 0.05 * spread) << "the repaired sphere is shaded as the true one";
  expect_one_line_error(run({zero, "--out", path("refused.png"), "--bad-normals", "refuse"}), 1,
                        "zero.ply: vertex 0 has a zero normal");
}

TEST_F(RenderCommand, BadArgumentsAreExitTwoBeforeAnythingIsRead) {
  // The model does not exist: these must fail on the argument, not on the file.
  const std::string missing = path("missing.ply");
  expect_one_line_error(run({missing, "--out", path("x.jpg")}), 2, "name it .png");
  const std::string file = path("a-file");
  std::ofstream(file) << "x";
  expect_one_line_error(run({missing, "--out", file + "/x.png"}), 2, "a-file is not a directory");
  // A folder is named as one, not blamed on its missing extension.
  expect_one_line_error(run({missing, "--out", folder_.string()}), 2, "is a directory, not a file to write");
  expect_one_line_error(run({missing, "--out", path("x.png"), "--size", "100"}), 2, "--size");
  expect_one_line_error(run({missing, "--out", path("x.png"), "--size", "8x8"}), 2, "--size");
  expect_one_line_error(run({missing, "--out", path("x.png"), "--view", "0,0,0"}), 2, "--view");
  expect_one_line_error(run({missing, "--out", folder_.string() + "/.png"}), 2, ".png");
  EXPECT_EQ(run({missing, "--out", path("x.png"), "--views", "0"}).status, 2);
  expect_one_line_error(run({missing, "--out", path("x.png"), "--views", "36", "--size", "4000x4000"}), 2,
                        "--views and --size: 36 x 1 views of 4000x4000 make 576 million pixels");
  EXPECT_FALSE(fs::exists(path("x.png")));
}

// A folder still missing on the picture's way is made when it is written, as run, replay and
// view make theirs: render refused it ("does not exist"), the only command that did.
TEST_F(RenderCommand, MissingFoldersOnThePicturesWayAreMade) {
  const std::string nested = path("new/deeper/x.png");
  const CommandResult made = run({sphere_, "--out", nested, "--size", "64x48"});
  ASSERT_EQ(made.status, 0) << made.output;
  EXPECT_EQ(read_png(nested).width, 64);
}

TEST_F(RenderCommand, UnreadableInputIsExitOneAndModelsOfDifferentSizesExitTwo) {
  expect_one_line_error(run({path("missing.ply"), "--out", path("x.png")}), 1, "missing.ply");
#if SCULPT_TEST_WITH_LCM
  expect_one_line_error(run({sphere_, "--log", path("missing.lcmlog"), "--out", path("x.png")}), 1, "missing.lcmlog");
#else
  expect_one_line_error(run({sphere_, "--log", path("missing.lcmlog"), "--out", path("x.png")}), 2,
                        "--log needs LCM; reconfigure with -DSCULPT_WITH_LCM=ON");
#endif
  const std::string other = path("other.ply");
  deform::write_model(other, deform::make_sphere(1999, 1.0));
  expect_one_line_error(run({sphere_, "--compare", other, "--out", path("x.png")}), 2, "1999 points");
  // Every point in one place: readable, but nothing to draw (no length scale for splats).
  deform::PointModel stack;
  for (int i = 0; i < 5; ++i) stack.push_back({1.0, 2.0, 3.0});
  const std::string stacked = path("stacked.xyz");
  deform::write_model(stacked, stack);
  expect_one_line_error(run({stacked, "--out", path("x.png")}), 1, "coincide");
  EXPECT_FALSE(fs::exists(path("x.png")));
}

// A real session: the bundled one-finger press run by the station, its durable log drawn over
// its sculpted model. The log's collisions are all read, and they are drawn where the press was:
// every pixel of the finger's overlay colour lies around the top of the sphere, on the axis the
// finger came down. (The camera fits model and overlay together, so the two pictures are not
// compared pixel by pixel.)
TEST_F(RenderCommand, DrawsTheLogOfARecordedSessionWhereThePressWas) {
#if !SCULPT_TEST_WITH_LCM
  GTEST_SKIP() << "built without LCM (-DSCULPT_WITH_LCM=OFF): the station records no event log to draw";
#endif
  const fs::path scene = copy_bundled_scene(folder_, "sphere-press");
  ChildProcess station({SCULPT_BINARY, "run", scene.string(), "--duration", "3.6", "--quiet"}, path("run.txt"));
  ASSERT_EQ(station.wait(std::chrono::seconds(60)), 0);
  std::ifstream summary_file(path("sphere-press.json"));
  const std::string summary((std::istreambuf_iterator<char>(summary_file)), {});
  const std::size_t at = summary.find("\"collisions\":");
  ASSERT_NE(at, std::string::npos) << summary;
  const long collisions = std::stol(summary.substr(at + 13));
  ASSERT_GT(collisions, 0);

  // Looking along +y with z up: the press came down the z axis onto the top of the picture.
  const std::vector<std::string> view = {"--view", "0,1,0", "--up", "z", "--size", "120x120"};
  std::vector<std::string> plain = {path("sphere-press.ply"), "--out", path("plain.png")};
  std::vector<std::string> drawn = {
      path("sphere-press.ply"), "--out", path("drawn.png"), "--log", path("sphere-press.lcmlog"), "--arrow-scale", "3"};
  plain.insert(plain.end(), view.begin(), view.end());
  drawn.insert(drawn.end(), view.begin(), view.end());
  ASSERT_EQ(run(plain).status, 0);
  const CommandResult r = run(drawn);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find(": " + std::to_string(collisions) + " collision events"), std::string::npos)
      << "every collision of the session (" << collisions << ") is read: " << r.output;

  // The index finger's overlay colour is a strong blue (0.15, 0.45, 0.95); the clay has none.
  auto blue_pixels = [](const render::Image& image, std::size_t& near_top_axis) {
    std::size_t count = 0;
    near_top_axis = 0;
    for (int y = 0; y < image.height; ++y) {
      for (int x = 0; x < image.width; ++x) {
        const std::uint8_t* c = image.at(x, y);
        if (!(c[2] > 150 && c[2] > c[0] + 60 && c[2] > c[1] + 40)) continue;
        ++count;
        near_top_axis += y < image.height / 3 && std::abs(x - image.width / 2) < image.width / 8;
      }
    }
    return count;
  };
  const render::Image plain_image = read_png(path("plain.png")), drawn_image = read_png(path("drawn.png"));
  ASSERT_EQ(plain_image.width, 120);
  ASSERT_EQ(drawn_image.width, 120);
  std::size_t plain_near = 0, drawn_near = 0;
  EXPECT_EQ(blue_pixels(plain_image, plain_near), 0u) << "the model alone has no overlay colour";
  const std::size_t blue = blue_pixels(drawn_image, drawn_near);
  EXPECT_GT(blue, 20u) << "the probes and arrows are drawn";
  EXPECT_EQ(drawn_near, blue) << "all of them around the top of the sphere, on the axis the finger came down";
}

}  // namespace
}  // namespace sculpt::test
