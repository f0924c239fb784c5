// From a scene to a station's settings: the defaults derived from the model's spacing, and the
// scene's lengths checked against the model once it is loaded, named by their scene keys.

#include <gtest/gtest.h>

#include <filesystem>
#include <stdexcept>
#include <string>
#include <utility>

#include "sculpt/deform/generators.hpp"
#include "sculpt/deform/model_io.hpp"
#include "sculpt/rt/station_setup.hpp"

namespace sculpt::rt {
namespace {

// The bundled unit sphere (diagonal 2 sqrt 3) and one scripted finger; `extra` adds tables.
Scene sphere_scene(const std::string& extra) {
  const std::string text = R"([model]
path = "data/sphere_3203.ply"
[glove]
backend = "sim"
[[glove.sim.script]]
finger = "index"
keyframes = [[0, 0, 0, 1.3]]
)" + extra;
  return parse_scene(text, "t.toml", SCULPT_SOURCE_DIR);
}

std::string refusal(const Scene& scene) {
  try {
    prepare_station(scene);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "accepted";
}

TEST(StationSetup, DerivedDefaultsSayWhichStatisticTheyCameFrom) {
  const StationSetup s = prepare_station(sphere_scene(""));
  EXPECT_EQ(s.spacing.statistic, "median nearest-neighbour distance over distinct points, 2000 samples");
  // The thesis's sphere: a spacing of about 0.06.
  EXPECT_NEAR(s.spacing.value, 0.06, 0.005);
  EXPECT_EQ(s.settings.deform.contact.bc_radius, s.spacing.value);
  ASSERT_FALSE(s.notes.empty());
  EXPECT_NE(s.notes.back().find("x the model's spacing"), std::string::npos) << s.notes.back();
}

TEST(StationSetup, AStrictRegionNeverRunsAsTheCheaperGlobalFrame) {
  EXPECT_TRUE(prepare_station(sphere_scene("[heuristic]\nregion = 0.5\n")).settings.deform.region.global_when_cheaper);
  EXPECT_FALSE(prepare_station(sphere_scene("[heuristic]\nregion = 0.5\nstrict_region = true\n"))
                   .settings.deform.region.global_when_cheaper);
}

TEST(StationSetup, LengthsFarBeyondTheModelAreRefusedNamingTheKey) {
  EXPECT_EQ(refusal(sphere_scene("[deform]\ndelta_d = 1e30\n")).rfind("t.toml: deform.delta_d = 1e+30 is too large", 0),
            0u)
      << refusal(sphere_scene("[deform]\ndelta_d = 1e30\n"));
  const std::pair<const char*, const char*> cases[] = {
      {"[deform]\nbc_radius = 4e3\n", "deform.bc_radius = 4000 is too large"},
      {"[deform]\ndelta_r = 4e3\n", "deform.delta_r = 4000 is too large"},
      {"[deform]\ndelta_s = 4e3\n", "deform.delta_s = 4000 is too large"}};
  for (const auto& [extra, expected] : cases) {
    const std::string message = refusal(sphere_scene(extra));
    EXPECT_NE(message.find(expected), std::string::npos) << message;
  }
  const std::string region = refusal(sphere_scene("[heuristic]\nregion = 1e9\n"));
  EXPECT_NE(region.find("heuristic.region = 1e+09 is too large"), std::string::npos) << region;
  const std::string eps = refusal(sphere_scene("[kernel]\nkind = \"regularized\"\neps = 1e9\n"));
  EXPECT_NE(eps.find("kernel.eps = 1e+09 is too large"), std::string::npos) << eps;
  // Within 1e3 diagonals (about 3464) is the scene's business.
  EXPECT_EQ(refusal(sphere_scene("[deform]\ndelta_r = 3e3\n")), "accepted");
}

// A reduced set too small to have a length scale is named by the ratio that made it.
TEST(StationSetup, AReducedRatioLeavingNoLengthScaleIsRefusedNamingTheKey) {
  EXPECT_EQ(refusal(sphere_scene("[heuristic]\nreduced_ratio = 1e-300\n")),
            "t.toml: heuristic.reduced_ratio = 1e-300 leaves 1 of 3203 points: the model's points all coincide: no "
            "length scale (it has a single point)");
  EXPECT_EQ(refusal(sphere_scene("[heuristic]\nreduced_ratio = 0.01\n")), "accepted");
}

// A region must hold its contact's neighbourhood and the pinned band inside its border: a radius
// not above bc_radius twice was refused only by the deformer, naming no key.
TEST(StationSetup, ARegionTooSmallForItsContactAndBorderIsRefusedNamingTheKey) {
  EXPECT_EQ(refusal(sphere_scene("[deform]\nbc_radius = 0.05\n[heuristic]\nregion = 0.1\n")),
            "t.toml: heuristic.region: radius 0.1 must exceed deform.bc_radius plus the region's border width (0.1)");
  EXPECT_EQ(refusal(sphere_scene("[deform]\nbc_radius = 0.05\n[heuristic]\nregion = 0.1001\n")), "accepted");
}

TEST(StationSetup, NanAndHugeMaterialsAreRefusedWhenTheSceneIsRead) {
  const std::pair<const char*, const char*> cases[] = {{"[deform]\ndelta_d = nan\n", "deform.delta_d"},
                                                       {"[deform]\nbc_radius = inf\n", "deform.bc_radius"},
                                                       {"[material]\nG = 1e16\n", "material.G"},
                                                       {"[material]\nG = nan\n", "material.G"}};
  for (const auto& [extra, key] : cases) {
    try {
      sphere_scene(extra);
      ADD_FAILURE() << "accepted " << extra;
    } catch (const SceneError& e) {
      EXPECT_EQ(e.key(), key) << e.what();
    }
  }
  EXPECT_NO_THROW(sphere_scene("[material]\nG = 1e15\n"));
}

// The scene's model goes through check_normals: zero normals re-estimated (or refused, as the
// scene says), long ones normalised, and the counts shown where the model's normals are named.
TEST(StationSetup, TheFilesBadNormalsAreRepairedOrRefusedAsTheSceneSays) {
  deform::PointModel sphere = deform::make_sphere(3203);
  for (std::size_t i = 0; i < sphere.size(); ++i) sphere.set_normal(i, sphere.normal(i) * 2.0);
  for (std::size_t i = 0; i < 12; ++i) sphere.set_normal(100 * i, {});
  const std::string path = ::testing::TempDir() + "station_setup_bad_normals.ply";
  deform::write_ply(path, sphere);
  const std::string model = "[model]\npath = \"" + path + "\"\n";
  const std::string glove =
      "[glove]\nbackend = \"sim\"\n[[glove.sim.script]]\nfinger = \"index\"\n"
      "keyframes = [[0, 0, 0, 1.3]]\n";
  const StationSetup repaired = prepare_station(parse_scene(model + glove, "t.toml", ""));
  EXPECT_EQ(repaired.normal_report.zero_or_nonfinite, 12u);
  EXPECT_EQ(repaired.normal_report.renormalised, 3203u - 12u);
  EXPECT_EQ(repaired.normals_source, "file (12 zero or non-finite normals re-estimated, 3,191 normalised)");
  const Scene refusing = parse_scene(model + "bad_normals = \"refuse\"\n" + glove, "t.toml", "");
  EXPECT_THROW(prepare_station(refusing), deform::ModelFileError);
  // Normals the scene replaces anyway need no policy: naming one is a slip.
  EXPECT_THROW(parse_scene(model + "normals = \"pca\"\nbad_normals = \"refuse\"\n" + glove, "t.toml", ""), SceneError);
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace sculpt::rt
