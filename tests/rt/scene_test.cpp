// Scene files: the bundled scenes parse to what their comments say, defaults are applied,
// paths resolve against the scene's directory, and every malformed scene names its key and
// line.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "sculpt/rt/scene.hpp"

namespace sculpt::rt {
namespace {

namespace fs = std::filesystem;

const std::string kSceneDir = std::string(SCULPT_SOURCE_DIR) + "/scenes";

Scene parse(const std::string& text, const std::string& base_dir = "/base") {
  return parse_scene(text, "t.toml", base_dir);
}

// The smallest scene there is: a model and a scripted finger (lines 1-7, so an appended table
// starts on line 8).
const std::string kMinimal = R"([model]
path = "m.ply"
[glove]
backend = "sim"
[[glove.sim.script]]
finger = "index"
keyframes = [[0, 0, 0, 1.3]]
)";

TEST(Scene, EveryBundledSceneParses) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(kSceneDir)) {
    if (entry.path().extension() != ".toml") continue;
    names.push_back(entry.path().filename().string());
    SCOPED_TRACE(entry.path().string());
    const Scene scene = load_scene(entry.path().string());
    EXPECT_EQ(scene.glove.config.backend, hal::Backend::kSim);
    EXPECT_FALSE(scene.glove.config.sim.fingers.empty());
    EXPECT_TRUE(fs::path(scene.model.path).is_absolute());
    // Scripts stay short: a run of each bundled scene takes seconds.
    for (const auto& script : scene.glove.config.sim.fingers) {
      EXPECT_LE(script.keyframes.back().time_s, 6.0);
    }
  }
  for (const char* expected : {"sphere-press.toml", "sphere-pull.toml", "sphere-squeeze.toml", "dragon-press.toml"}) {
    EXPECT_NE(std::find(names.begin(), names.end(), expected), names.end()) << expected;
  }
}

TEST(Scene, SpherePressIsOneIndexFingerPressingFromAbove) {
  const Scene s = load_scene(kSceneDir + "/sphere-press.toml");
  EXPECT_EQ(s.model.path,
            fs::path(std::string(SCULPT_SOURCE_DIR) + "/data/sphere_3203.ply").lexically_normal().string());
  EXPECT_EQ(s.model.normals, NormalsSource::kAuto);
  EXPECT_EQ(s.deform.mode, deform::ContactMode::kPush);
  EXPECT_DOUBLE_EQ(s.loop.rate_hz, 1000.0);
  EXPECT_DOUBLE_EQ(s.glove.config.sim.rate_hz, 80.0);
  ASSERT_EQ(s.glove.config.sim.fingers.size(), 1u);
  const auto& script = s.glove.config.sim.fingers[0];
  EXPECT_EQ(script.hand, 0);
  EXPECT_EQ(script.finger, 1);
  EXPECT_DOUBLE_EQ(script.keyframes.front().z, 1.3);
  double lowest = 10.0;
  for (const auto& k : script.keyframes) lowest = std::min(lowest, k.z);
  EXPECT_DOUBLE_EQ(lowest, 0.92);
  EXPECT_DOUBLE_EQ(script.keyframes.back().z, 1.3);  // released
  EXPECT_EQ(s.glove.fingers, (std::vector<std::uint8_t>{1}));
  EXPECT_DOUBLE_EQ(s.registration.scale, 1.0);
  EXPECT_EQ(s.registration.rotation, (std::array<double, 4>{1, 0, 0, 0}));
  EXPECT_TRUE(s.registration.landmarks.empty());
  ASSERT_TRUE(s.output.model);
  EXPECT_EQ(*s.output.model,
            fs::path(std::string(SCULPT_SOURCE_DIR) + "/out/sphere-press.ply").lexically_normal().string());
}

TEST(Scene, SpherePullStartsInsideAndEndsOutside) {
  const Scene s = load_scene(kSceneDir + "/sphere-pull.toml");
  EXPECT_EQ(s.deform.mode, deform::ContactMode::kPull);
  const auto& k = s.glove.config.sim.fingers.at(0).keyframes;
  EXPECT_DOUBLE_EQ(k.front().z, 0.9);
  double highest = 0.0;
  for (const auto& f : k) highest = std::max(highest, f.z);
  EXPECT_DOUBLE_EQ(highest, 1.08);
}

TEST(Scene, SphereSqueezePressesFromThreeDirectionsAtOnce) {
  const Scene s = load_scene(kSceneDir + "/sphere-squeeze.toml");
  ASSERT_EQ(s.glove.config.sim.fingers.size(), 3u);
  EXPECT_EQ(s.glove.fingers, (std::vector<std::uint8_t>{0, 1, 2}));
  for (const auto& script : s.glove.config.sim.fingers) {
    const auto& start = script.keyframes.front();
    const auto& pressed = script.keyframes.at(1);
    EXPECT_NEAR(std::hypot(start.x, start.y, start.z), 1.3, 1e-4);
    EXPECT_NEAR(std::hypot(pressed.x, pressed.y, pressed.z), 0.92, 1e-4);
    EXPECT_DOUBLE_EQ(pressed.time_s, 1.0);  // all three press together
  }
}

TEST(Scene, DragonPressUsesTheFetchedScanAndAnAutomaticRegion) {
  const Scene s = load_scene(kSceneDir + "/dragon-press.toml");
  EXPECT_EQ(fs::path(s.model.path).filename(), "dragon_100250.ply");
  EXPECT_EQ(s.heuristic.region, RegionChoice::kAuto);
  const auto& k = s.glove.config.sim.fingers.at(0).keyframes;
  // Inside the scan's bounding box (x -0.108..0.096, y 0.053..0.197, z -0.050..0.041).
  for (const auto& f : k) {
    EXPECT_GT(f.x, -0.108);
    EXPECT_LT(f.x, 0.096);
    EXPECT_GT(f.z, -0.050);
    EXPECT_LT(f.z, 0.041);
  }
  // Starts above its back (the surface is at y = 0.1624 there) and presses a little in.
  EXPECT_GT(k.front().y, 0.17);
  double lowest = 1.0;
  for (const auto& f : k) lowest = std::min(lowest, f.y);
  EXPECT_LT(lowest, 0.1624);
  EXPECT_GT(lowest, 0.155);
}

TEST(Scene, DefaultsAreApplied) {
  const Scene s = parse(kMinimal);
  EXPECT_EQ(s.file, "t.toml");
  EXPECT_EQ(s.model.normals, NormalsSource::kAuto);
  EXPECT_FALSE(s.model.reference);
  EXPECT_DOUBLE_EQ(s.material.shear_modulus, 3e7);
  EXPECT_DOUBLE_EQ(s.material.poisson_ratio, 0.45);
  EXPECT_EQ(s.kernel.kind, deform::KernelKind::kKelvin);
  EXPECT_EQ(s.kernel.eps, 0.0);
  EXPECT_EQ(s.deform.form, deform::WeightForm::kForce);
  EXPECT_EQ(s.deform.mode, deform::ContactMode::kPush);
  // Left to the model's spacing, found when it loads.
  EXPECT_FALSE(s.deform.bc_radius);
  EXPECT_FALSE(s.deform.delta_s);
  EXPECT_FALSE(s.deform.delta_d);
  EXPECT_FALSE(s.deform.delta_r);
  EXPECT_EQ(s.deform.precision, deform::Precision::kFloat);
  EXPECT_TRUE(s.deform.carry_normals);
  EXPECT_FALSE(s.deform.fast_inverse_sqrt);
  EXPECT_DOUBLE_EQ(s.deform.border_weight, 1.0);
  EXPECT_EQ(s.deform.threads, 1);
  EXPECT_EQ(s.heuristic.region, RegionChoice::kGlobal);
  EXPECT_DOUBLE_EQ(s.heuristic.budget_fraction, 0.6);
  EXPECT_DOUBLE_EQ(s.heuristic.reduced_ratio, 1.0);
  EXPECT_FALSE(s.heuristic.strict_region);
  EXPECT_DOUBLE_EQ(s.glove.timeout_ms, 100.0);
  EXPECT_EQ(s.glove.config.queue_capacity, 1024u);
  EXPECT_EQ(s.glove.hands, (std::vector<std::uint8_t>{0}));
  EXPECT_EQ(s.glove.fingers, (std::vector<std::uint8_t>{1}));  // the scripted finger
  EXPECT_DOUBLE_EQ(s.glove.config.sim.rate_hz, 80.0);
  EXPECT_EQ(s.glove.config.sim.seed, 1u);
  EXPECT_EQ(s.glove.config.sim.jitter_stddev, 0.0);
  EXPECT_FALSE(s.glove.config.sim.repeat);
  EXPECT_EQ(s.hand.kind, hal::SampleKind::kPositions);
  EXPECT_FALSE(s.hand.bone_lengths);
  EXPECT_TRUE(s.filter.enabled);
  EXPECT_DOUBLE_EQ(s.filter.min_cutoff, 1.0);
  EXPECT_DOUBLE_EQ(s.filter.beta, 0.1);
  EXPECT_DOUBLE_EQ(s.filter.d_cutoff, 1.0);
  EXPECT_DOUBLE_EQ(s.registration.scale, 1.0);
  EXPECT_EQ(s.registration.rotation, (std::array<double, 4>{1, 0, 0, 0}));
  EXPECT_EQ(s.registration.translation, deform::Vec3{});
  EXPECT_EQ(s.haptic.sink, hal::SinkKind::kNone);
  EXPECT_DOUBLE_EQ(s.loop.rate_hz, 1000.0);
  EXPECT_EQ(s.loop.realtime, RealtimeMode::kOff);
  EXPECT_FALSE(s.loop.lock_memory);
  EXPECT_EQ(s.loop.cpu, -1);
  EXPECT_EQ(s.lcm.url, "udpm://239.255.76.67:7667?ttl=0");
  EXPECT_FALSE(s.lcm.publish);
  EXPECT_FALSE(s.output.model);
  EXPECT_FALSE(s.output.log);
  EXPECT_FALSE(s.output.json);
  EXPECT_DOUBLE_EQ(s.output.flush_interval_ms, 100.0);
  EXPECT_DOUBLE_EQ(s.output.tick_interval_ms, 100.0);
}

TEST(Scene, RelativePathsResolveAgainstTheSceneDirectory) {
  const Scene s = parse(R"([model]
path = "../models/m.PLY"
[glove]
backend = "sim"
[[glove.sim.script]]
finger = 1
keyframes = [[0, 0, 0, 1.3]]
[output]
model = "out/final.ply"
log = "/abs/events.lcmlog"
json = "./summary.json"
)",
                        "/work/scenes");
  EXPECT_EQ(s.model.path, "/work/models/m.PLY");
  EXPECT_EQ(*s.output.model, "/work/scenes/out/final.ply");
  EXPECT_EQ(*s.output.log, "/abs/events.lcmlog");
  EXPECT_EQ(*s.output.json, "/work/scenes/summary.json");
}

TEST(Scene, LoadSceneResolvesAgainstTheFilesOwnDirectory) {
  const fs::path dir = fs::temp_directory_path() / "sculpt_scene_test" / "nested";
  fs::create_directories(dir);
  const fs::path file = dir / "s.toml";
  std::ofstream(file) << kMinimal << "[output]\nmodel = \"../o.ply\"\n";
  const Scene s = load_scene(file.string());
  EXPECT_EQ(s.model.path, (dir / "m.ply").string());
  EXPECT_EQ(*s.output.model, (dir.parent_path() / "o.ply").string());
  EXPECT_EQ(s.base_dir, dir.string());
  fs::remove_all(dir.parent_path());
}

// The axis is normalised without squaring it: an axis of 1e300 (or 1e-300) squared to inf (or
// 0), which gave a rotation of norm cos(angle / 2) (or "the axis must not be zero").
TEST(Scene, AnAxisAngleOfAnyFiniteAxisLengthIsAUnitRotation) {
  const double h = std::sqrt(0.5);
  for (const char* axis : {"1e300, 1e300, 0", "1e-300, 1e-300, 0", "2, 2, 0"}) {
    const Scene s =
        parse_scene(kMinimal + "[registration]\naxis_angle = [" + axis + ", 3.141592653589793]\n", "t.toml", "/base");
    const auto& q = s.registration.rotation;
    EXPECT_NEAR(q[0], 0.0, 1e-15) << axis;
    EXPECT_NEAR(q[1], h, 1e-15) << axis;
    EXPECT_NEAR(q[2], h, 1e-15) << axis;
    EXPECT_EQ(q[3], 0.0) << axis;
  }
}

TEST(Scene, AnUnreadableFileIsNamed) {
  try {
    load_scene("/nonexistent/scene.toml");
    FAIL() << "no error";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.key(), "file");
    EXPECT_EQ(std::string(e.what()), "/nonexistent/scene.toml: file: cannot open (No such file or directory)");
  }
}

TEST(Scene, EveryBackendFillsItsConfig) {
  const std::string model = "[model]\npath = \"m.ply\"\n";
  {
    const Scene s = parse(model + R"([glove]
backend = "serial"
[glove.serial]
device = "/dev/ttyUSB0"
baud = 115200
reconnect_ms = 500
)");
    EXPECT_EQ(s.glove.config.backend, hal::Backend::kSerial);
    EXPECT_EQ(s.glove.config.serial.device, "/dev/ttyUSB0");
    EXPECT_EQ(s.glove.config.serial.baud, 115200);
    EXPECT_DOUBLE_EQ(s.glove.config.serial.reconnect_interval_ms, 500.0);
    EXPECT_EQ(s.glove.hands, (std::vector<std::uint8_t>{0}));
    EXPECT_EQ(s.glove.fingers, (std::vector<std::uint8_t>{0, 1, 2, 3, 4}));
  }
  {
    const Scene s = parse(model + R"([glove]
backend = "usb"
hands = [1, 0]
fingers = ["little", 0]
[glove.usb]
vendor_id = 0x1209
product_id = 0xA7C3
interface = 2
endpoint = 0x82
transfer = "bulk"
)");
    const auto& usb = s.glove.config.usb;
    EXPECT_EQ(usb.vendor_id, 0x1209);
    EXPECT_EQ(usb.product_id, 0xA7C3);
    EXPECT_EQ(usb.interface_number, 2);
    EXPECT_EQ(usb.endpoint, 0x82);
    EXPECT_EQ(usb.transfer, hal::UsbConfig::Transfer::kBulk);
    EXPECT_EQ(s.glove.hands, (std::vector<std::uint8_t>{0, 1}));
    EXPECT_EQ(s.glove.fingers, (std::vector<std::uint8_t>{0, 4}));
  }
  {
    const Scene s = parse(model + R"([lcm]
url = "memq://"
[glove]
backend = "lcm"
[glove.lcm]
channel = "GLOVE_A"
[haptic]
sink = "lcm"
[haptic.lcm]
)");
    EXPECT_EQ(s.glove.config.lcm.url, "memq://");  // the scene's LCM URL by default
    EXPECT_EQ(s.glove.config.lcm.glove_channel, "GLOVE_A");
    EXPECT_EQ(s.haptic.sink, hal::SinkKind::kLcm);
    EXPECT_EQ(s.haptic.lcm.url, "memq://");
    EXPECT_EQ(s.haptic.lcm.haptic_channel, "SCULPT_HAPTIC");
  }
  {
    const Scene s = parse(model + R"([glove]
backend = "socketcan"
[glove.socketcan]
interface = "vcan0"
fd = false
base_id = 0x200
[haptic]
sink = "serial"
queue_capacity = 64
[haptic.serial]
device = "/dev/ttyACM1"
)");
    EXPECT_EQ(s.glove.config.can.interface, "vcan0");
    EXPECT_FALSE(s.glove.config.can.fd);
    EXPECT_EQ(s.glove.config.can.base_id, 0x200u);
    EXPECT_EQ(s.haptic.sink, hal::SinkKind::kSerial);
    EXPECT_EQ(s.haptic.queue_capacity, 64u);
    EXPECT_EQ(s.haptic.serial.device, "/dev/ttyACM1");
  }
  {
    const Scene s = parse(model + R"([glove]
backend = "usb"
[glove.usb]
vendor_id = 0x1209
product_id = 0xA7C3
[haptic]
sink = "usb"
max_force = 2.5
[haptic.usb]
vendor_id = 0x1209
product_id = 0xA7C3
out_endpoint = 0x02
transfer = "bulk"
)");
    EXPECT_EQ(s.haptic.sink, hal::SinkKind::kUsb);
    const auto& usb = s.haptic.usb;
    EXPECT_EQ(usb.vendor_id, 0x1209);
    EXPECT_EQ(usb.product_id, 0xA7C3);
    EXPECT_EQ(usb.interface_number, 1);  // the glove source's is 0: an interface is claimed once
    EXPECT_EQ(usb.out_endpoint, 0x02);
    EXPECT_EQ(usb.transfer, hal::UsbConfig::Transfer::kBulk);
    EXPECT_DOUBLE_EQ(s.haptic.max_force, 2.5);  // the sink bounds the forces again, to the same limit
    EXPECT_DOUBLE_EQ(s.haptic_limits.max_force, 2.5);
  }
}

TEST(Scene, EverySectionReadsItsKeys) {
  const Scene s = parse(R"([model]
path = "m.xyz"
reference = [0, 0, 10]
[material]
G = 1e6
nu = 0.5
[kernel]
kind = "regularized"
eps = 0.02
[deform]
form = "force"
bc_radius = 0.05
delta_s = 0.001
delta_d = 0.01
delta_r = 0.1
precision = "double"
carry_normals = false
border_weight = 2.5
threads = 2
[heuristic]
region = 0.3
budget_fraction = 0.5
reduced_ratio = 0.25
strict_region = true
[glove]
backend = "serial"
timeout_ms = 40
queue_capacity = 256
[glove.serial]
device = "/dev/pts/3"
[hand]
kind = "angles"
bone_lengths = [[0.04, 0.03, 0.03], [0.045, 0.025, 0.02], [0.05, 0.03, 0.02],
                [0.045, 0.028, 0.02], [0.035, 0.02, 0.018]]
[filter]
enabled = false
min_cutoff = 2.0
beta = 0.5
d_cutoff = 3
[registration]
scale = 0.001
axis_angle = [0, 0, 2, 3.141592653589793]
translation = [0.1, 0.2, 0.3]
[loop]
rate_hz = 500
realtime = true
lock_memory = true
cpu = 1
[lcm]
publish = true
[output]
log = "e.lcmlog"
flush_interval_ms = 20
tick_interval_ms = 0
)");
  EXPECT_EQ(s.model.normals, NormalsSource::kNone);  // a reference point replaces normals
  EXPECT_EQ(*s.model.reference, (deform::Vec3{0, 0, 10}));
  EXPECT_DOUBLE_EQ(s.material.poisson_ratio, 0.5);
  EXPECT_EQ(s.kernel.kind, deform::KernelKind::kRegularized);
  EXPECT_DOUBLE_EQ(s.kernel.eps, 0.02);
  EXPECT_EQ(s.deform.form, deform::WeightForm::kForce);
  EXPECT_DOUBLE_EQ(*s.deform.bc_radius, 0.05);
  EXPECT_DOUBLE_EQ(*s.deform.delta_s, 0.001);
  EXPECT_DOUBLE_EQ(*s.deform.delta_d, 0.01);
  EXPECT_DOUBLE_EQ(*s.deform.delta_r, 0.1);
  EXPECT_EQ(s.deform.precision, deform::Precision::kDouble);
  EXPECT_FALSE(s.deform.carry_normals);
  EXPECT_DOUBLE_EQ(s.deform.border_weight, 2.5);
  EXPECT_EQ(s.deform.threads, 2);
  EXPECT_EQ(s.heuristic.region, RegionChoice::kRadius);
  EXPECT_DOUBLE_EQ(s.heuristic.region_radius, 0.3);
  EXPECT_DOUBLE_EQ(s.heuristic.reduced_ratio, 0.25);
  EXPECT_TRUE(s.heuristic.strict_region);
  EXPECT_DOUBLE_EQ(s.glove.timeout_ms, 40.0);
  EXPECT_EQ(s.glove.config.queue_capacity, 256u);
  EXPECT_EQ(s.hand.kind, hal::SampleKind::kAngles);
  EXPECT_DOUBLE_EQ((*s.hand.bone_lengths)[4][2], 0.018);
  EXPECT_FALSE(s.filter.enabled);
  EXPECT_DOUBLE_EQ(s.filter.d_cutoff, 3.0);
  // A half turn about z (the axis need not be unit length).
  EXPECT_NEAR(s.registration.rotation[0], 0.0, 1e-15);
  EXPECT_NEAR(s.registration.rotation[3], 1.0, 1e-15);
  EXPECT_EQ(s.registration.translation, (deform::Vec3{0.1, 0.2, 0.3}));
  EXPECT_DOUBLE_EQ(s.loop.rate_hz, 500.0);
  EXPECT_EQ(s.loop.realtime, RealtimeMode::kTry);  // true means "try"
  EXPECT_EQ(s.loop.cpu, 1);
  EXPECT_TRUE(s.lcm.publish);
  EXPECT_EQ(*s.output.log, "/base/e.lcmlog");
  EXPECT_DOUBLE_EQ(s.output.flush_interval_ms, 20.0);
  EXPECT_DOUBLE_EQ(s.output.tick_interval_ms, 0.0);
}

TEST(Scene, FastInverseSqrtIsReadInFloat) {
  EXPECT_TRUE(parse(kMinimal + "[deform]\nfast_inverse_sqrt = true\n").deform.fast_inverse_sqrt);
}

TEST(Scene, LandmarksAreParsed) {
  const Scene s = parse(kMinimal + R"([registration]
landmarks = [
  { glove = [0, 0, 0], model = [1, 1, 1] },
  { glove = [1, 0, 0], model = [2, 1, 1] },
  { glove = [0, 1, 0], model = [1, 2, 1] },
]
)");
  ASSERT_EQ(s.registration.landmarks.size(), 3u);
  EXPECT_EQ(s.registration.landmarks[2].model, (deform::Vec3{1, 2, 1}));
}

TEST(Scene, AQuaternionIsNormalised) {
  const Scene s = parse(kMinimal + "[registration]\nrotation = [0.7071, 0, 0, 0.7071]\n");
  const auto& q = s.registration.rotation;
  EXPECT_NEAR(q[0] * q[0] + q[3] * q[3], 1.0, 1e-15);
}

struct Malformed {
  const char* name;
  std::string text;
  const char* key;
  int line;
  const char* problem;  // a part of the message after the key
};

/// A sim-glove scene whose [glove] table holds `line`, on line 5.
std::string glove_scene(const std::string& line) {
  return "[model]\npath = \"m.ply\"\n[glove]\nbackend = \"sim\"\n" + line +
         "\n[[glove.sim.script]]\nfinger = 1\nkeyframes = [[0, 0, 0, 1]]\n";
}

/// A sim-glove scene whose [glove.sim] table holds `line`, on line 6.
std::string sim_scene(const std::string& line) {
  return "[model]\npath = \"m.ply\"\n[glove]\nbackend = \"sim\"\n[glove.sim]\n" + line +
         "\n[[glove.sim.script]]\nfinger = \"index\"\nkeyframes = [[0, 0, 0, 1]]\n";
}

// Line numbers below count from the start of each text; kMinimal is 7 lines.
std::vector<Malformed> malformed_scenes() {
  return {
      {"typo at the top level", kMinimal + "[modle]\npath = \"x.ply\"\n", "modle", 8, "unknown key"},
      {"typo in model", "[model]\npth = \"m.ply\"\n", "model.pth", 2, "unknown key"},
      {"typo in glove", "[model]\npath = \"m.ply\"\n[glove]\nbackend = \"sim\"\ntimout_ms = 5\n", "glove.timout_ms", 5,
       "unknown key"},
      {"typo in glove.sim", R"([model]
path = "m.ply"
[glove]
backend = "sim"
[glove.sim]
rate_hz = 80
ratee = 80
[[glove.sim.script]]
finger = "index"
keyframes = [[0, 0, 0, 1]]
)",
       "glove.sim.ratee", 7, "unknown key"},
      {"typo as a dotted key", R"([model]
path = "m.ply"
[glove]
backend = "sim"
timeout_ms = 50
sim.ratee = 3
[[glove.sim.script]]
finger = "index"
keyframes = [[0, 0, 0, 1]]
)",
       "glove.sim.ratee", 6, "unknown key"},
      {"typo in a script", R"([model]
path = "m.ply"
[glove]
backend = "sim"
[[glove.sim.script]]
finger = "index"
keyframes = [[0, 0, 0, 1]]
[[glove.sim.script]]
fingr = "thumb"
keyframes = [[0, 0, 0, 1]]
)",
       "glove.sim.script[1].fingr", 9, "unknown key"},
      {"typo in a landmark", kMinimal + R"([registration]
landmarks = [
  { glove = [0, 0, 0], model = [1, 1, 1] },
  { glove = [1, 0, 0], modle = [2, 1, 1] },
  { glove = [0, 1, 0], model = [1, 2, 1] },
]
)",
       "registration.landmarks[1].modle", 11, "unknown key"},
      {"typo in deform", kMinimal + "[deform]\nmode = \"push\"\nbc_raduis = 0.1\n", "deform.bc_raduis", 10,
       "unknown key"},
      {"number given as a string", kMinimal + "[deform]\ndelta_s = \"0.1\"\n", "deform.delta_s", 9,
       "expected a number, got string"},
      {"boolean given as a number", kMinimal + "[filter]\nenabled = 1\n", "filter.enabled", 9, "expected a boolean"},
      {"integer given as a float", kMinimal + "[loop]\ncpu = 1.5\n", "loop.cpu", 9, "expected an integer, got float"},
      {"a table given as a value", "deform = 3\n" + kMinimal, "deform", 1, "expected a table, got integer"},
      {"loop rate too low", kMinimal + "[loop]\nrate_hz = 20\n", "loop.rate_hz", 9,
       "out of range: 20 is not in [50, 2000]"},
      {"loop rate too high", kMinimal + "[loop]\nrate_hz = 5000\n", "loop.rate_hz", 9, "out of range"},
      {"three threads", kMinimal + "[deform]\nthreads = 3\n", "deform.threads", 9, "out of range: 3 is not in [1, 2]"},
      {"nu above 0.5", kMinimal + "[material]\nnu = 0.6\n", "material.nu", 9, "out of range: 0.6 is not in (-1, 0.5]"},
      {"nu at -1", kMinimal + "[material]\nG = 1e6\nnu = -1\n", "material.nu", 10, "out of range"},
      {"negative G", kMinimal + "[material]\nG = -5\n", "material.G", 9, "must be > 0"},
      {"huge G", kMinimal + "[material]\nG = 2e15\n", "material.G", 9, "out of range: 2e+15 is above 1e15"},
      // A G of 1e-36 passed and made every frame non-finite: the station sculpted nothing.
      {"tiny G", kMinimal + "[material]\nG = 1e-36\n", "material.G", 9, "out of range: 1e-36 is below 1e-15"},
      {"negative bc radius", kMinimal + "[deform]\nbc_radius = -0.1\n", "deform.bc_radius", 9, "must be > 0"},
      {"negative region radius", kMinimal + "[heuristic]\nregion = -2\n", "heuristic.region", 9, "must be > 0"},
      {"budget above 1", kMinimal + "[heuristic]\nbudget_fraction = 1.5\n", "heuristic.budget_fraction", 9,
       "out of range"},
      {"infinite jitter", sim_scene("jitter = inf"), "glove.sim.jitter", 6, "must be finite"},
      {"unknown mode", kMinimal + "[deform]\nmode = \"pul\"\n", "deform.mode", 9,
       "unknown value 'pul'; expected 'push' or 'pull'"},
      {"unknown backend", "[model]\npath = \"m.ply\"\n[glove]\nbackend = \"bluetooth\"\n", "glove.backend", 4,
       "expected 'sim', 'serial', 'usb', 'lcm' or 'socketcan'"},
      {"unknown region word", kMinimal + "[heuristic]\nregion = \"local\"\n", "heuristic.region", 9,
       "expected 'global', 'auto' or a radius"},
      {"unknown finger", R"([model]
path = "m.ply"
[glove]
backend = "sim"
[[glove.sim.script]]
finger = "pinky"
keyframes = [[0, 0, 0, 1]]
)",
       "glove.sim.script[0].finger", 6, "unknown finger 'pinky'"},
      {"hand out of range", R"([model]
path = "m.ply"
[glove]
backend = "sim"
hands = [0,
         2]
[[glove.sim.script]]
finger = "index"
keyframes = [[0, 0, 0, 1]]
)",
       "glove.hands[1]", 6, "hand 2 is not 0 or 1"},
      {"missing model.path", "[model]\nnormals = \"pca\"\n[glove]\nbackend = \"sim\"\n", "model.path", 1,
       "missing required key"},
      {"missing model section", "\n\n[glove]\nbackend = \"sim\"\n", "model.path", 1, "missing required key"},
      {"missing glove backend", "[model]\npath = \"m.ply\"\n[glove]\ntimeout_ms = 10\n", "glove.backend", 3,
       "missing required key"},
      {"unsupported model format", "[model]\npath = \"m.stl\"\n", "model.path", 2, "expected .ply, .off or .xyz"},
      {"another backend's section", kMinimal + "[glove.usb]\nvendor_id = 0x1234\n", "glove.usb", 8,
       "backend is 'sim'; remove this section or change glove.backend"},
      {"serial backend without its section", "[model]\npath = \"m.ply\"\n[glove]\nbackend = \"serial\"\n",
       "glove.serial", 4, "this section is missing"},
      {"serial backend without a device",
       "[model]\npath = \"m.ply\"\n[glove]\nbackend = \"serial\"\n[glove.serial]\nbaud = 9600\n", "glove.serial.device",
       5, "missing required key"},
      {"usb ids as strings",
       "[model]\npath = \"m.ply\"\n[glove]\nbackend = \"usb\"\n[glove.usb]\nvendor_id = \"0x1234\"\nproduct_id = 1\n",
       "glove.usb.vendor_id", 6, "expected an integer, got string"},
      {"usb IN endpoint without its direction bit",
       "[model]\npath = \"m.ply\"\n[glove]\nbackend = \"usb\"\n[glove.usb]\nvendor_id = 1\nproduct_id = 1\nendpoint = "
       "0x01\n",
       "glove.usb.endpoint", 8, "out of range"},
      {"toml syntax error", kMinimal + "[loop]\nrate_hz = = 3\n", "toml", 9, ""},
      {"duplicate key", kMinimal + "[loop]\nrate_hz = 100\nrate_hz = 200\n", "toml", 10, ""},
      {"keyframe with three numbers", R"([model]
path = "m.ply"
[glove]
backend = "sim"
[[glove.sim.script]]
finger = "index"
keyframes = [
  [0.0, 0, 0, 1.3],
  [1.0, 0, 0.9],
]
)",
       "glove.sim.script[0].keyframes[1]", 9, "expected [t, x, y, z], got 3 elements"},
      {"keyframe coordinate as a string", R"([model]
path = "m.ply"
[glove]
backend = "sim"
[[glove.sim.script]]
finger = "index"
keyframes = [[0.0, 0, 0, "1.3"]]
)",
       "glove.sim.script[0].keyframes[0][3]", 7, "expected a number, got string"},
      {"keyframes going backwards", R"([model]
path = "m.ply"
[glove]
backend = "sim"
[[glove.sim.script]]
finger = "index"
keyframes = [
  [0.0, 0, 0, 1.3],
  [1.0, 0, 0, 0.9],
  [0.5, 0, 0, 1.3],
]
)",
       "glove.sim.script[0].keyframes[2]", 10, "time 0.5 s is not after the previous keyframe's 1 s"},
      {"two scripts for one finger", kMinimal + "[[glove.sim.script]]\nfinger = 1\nkeyframes = [[0, 0, 0, 1]]\n",
       "glove.sim.script[1]", 8, "already has a script"},
      {"sim without a script", "[model]\npath = \"m.ply\"\n[glove]\nbackend = \"sim\"\n[glove.sim]\nrate_hz = 80\n",
       "glove.sim.script", 5, "missing required key"},
      {"landmarks fewer than 3", kMinimal + R"([registration]
landmarks = [
  { glove = [0, 0, 0], model = [1, 1, 1] },
  { glove = [1, 0, 0], model = [2, 1, 1] },
]
)",
       "registration.landmarks", 9, "needs at least 3 landmarks, got 2"},
      {"landmarks on a line", kMinimal + R"([registration]
landmarks = [
  { glove = [0, 0, 0], model = [1, 1, 1] },
  { glove = [1, 0, 0], model = [2, 1, 1] },
  { glove = [2, 0, 0], model = [3, 1, 1] },
]
)",
       "registration.landmarks", 9, "lie on one line"},
      {"landmarks with an explicit transform", kMinimal + R"([registration]
scale = 2
landmarks = [
  { glove = [0, 0, 0], model = [1, 1, 1] },
  { glove = [1, 0, 0], model = [2, 1, 1] },
  { glove = [0, 1, 0], model = [1, 2, 1] },
]
)",
       "registration.scale", 9, "not used with registration.landmarks"},
      {"rotation and axis angle", kMinimal + "[registration]\nrotation = [1, 0, 0, 0]\naxis_angle = [0, 0, 1, 0]\n",
       "registration.axis_angle", 10, "not both"},
      {"quaternion not unit", kMinimal + "[registration]\nrotation = [1, 0, 0, 0.5]\n", "registration.rotation", 9,
       "not a unit quaternion"},
      {"haptic sink without its section", kMinimal + "[haptic]\nsink = \"lcm\"\n", "haptic.lcm", 9,
       "haptic.sink is 'lcm' but this section is missing"},
      {"haptic section without a sink", kMinimal + "[haptic.can]\ninterface = \"can0\"\n", "haptic.can", 8,
       "sink is 'none'; remove this section or change haptic.sink"},
      {"haptic without normals", R"([model]
path = "m.xyz"
reference = [0, 0, 5]
[glove]
backend = "sim"
[[glove.sim.script]]
finger = "index"
keyframes = [[0, 0, 0, 1]]
[haptic]
sink = "can"
[haptic.can]
)",
       "haptic.sink", 10, "needs normals"},
      {"usb haptic sink on the interface the usb glove source claims", R"([model]
path = "m.ply"
[glove]
backend = "usb"
[glove.usb]
vendor_id = 0x1209
product_id = 1
[haptic]
sink = "usb"
[haptic.usb]
vendor_id = 0x1209
product_id = 1
interface = 0
)",
       "haptic.usb.interface", 13, "the glove source claims interface 0 of this device"},
      {"regularized kernel without eps", kMinimal + "[kernel]\nkind = \"regularized\"\n", "kernel.eps", 9,
       "missing required key (kernel.kind is 'regularized')"},
      {"eps with the kelvin kernel", kMinimal + "[kernel]\neps = 0.1\n", "kernel.eps", 9,
       "only used with kernel.kind = 'regularized'"},
      {"no normals and no reference", "[model]\npath = \"m.ply\"\nnormals = \"none\"\n", "model.normals", 3,
       "needs model.reference"},
      {"reference with computed normals", "[model]\npath = \"m.ply\"\nnormals = \"pca\"\nreference = [0, 0, 9]\n",
       "model.reference", 4, "only used with model.normals = 'none'"},
      {"border weight on a global region", kMinimal + "[deform]\nborder_weight = 2\n", "deform.border_weight", 9,
       "only used with a localised region"},
      {"strict region on a global region", kMinimal + "[heuristic]\nstrict_region = true\n", "heuristic.strict_region",
       9, "only used with a localised region"},
      {"fast 1/r in double", kMinimal + "[deform]\nprecision = \"double\"\nfast_inverse_sqrt = true\n",
       "deform.fast_inverse_sqrt", 10, "only the float loop has it"},
      {"angles from the sim glove", kMinimal + "[hand]\nkind = \"angles\"\n", "hand.kind", 9,
       "sim glove sends fingertip positions"},
      {"flush interval without a log", kMinimal + "[output]\nflush_interval_ms = 50\n", "output.flush_interval_ms", 9,
       "only used with output.log"},
      {"tick interval without a log", kMinimal + "[output]\ntick_interval_ms = 50\n", "output.tick_interval_ms", 9,
       "only used with output.log"},
      {"output overwrites the model", kMinimal + "[output]\nmodel = \"./m.ply\"\n", "output.model", 9,
       "would overwrite"},
      // A NUL ends a path for the system: "p.txt\u0000.ply" passed the extension check and then
      // wrote the model over p.txt; a model path cut there read another file.
      {"NUL in an output path", kMinimal + "[output]\nmodel = \"p.txt\\u0000.ply\"\n", "output.model", 9,
       "holds a NUL character (\\u0000) at position 5: a path or name would end there"},
      {"NUL in the model path", "[model]\npath = \"m\\u0000.ply\"\n", "model.path", 2,
       "holds a NUL character (\\u0000) at position 1"},
      {"a CPU past the pinning's set", kMinimal + "[loop]\ncpu = 4095\n", "loop.cpu", 9,
       "out of range: 4095 is not in [-1, 1023]"},
      {"zero glove timeout", glove_scene("timeout_ms = 0"), "glove.timeout_ms", 5,
       "out of range: 0 is not in (0, 3.6e+06] (milliseconds: at most an hour)"},
      // Times, timeouts and rates are bounded above: 1e13 ms added to a clock overflows int64
      // nanoseconds and made every hand stale at once.
      {"glove timeout of 1e13 ms", glove_scene("timeout_ms = 1e13"), "glove.timeout_ms", 5,
       "out of range: 1e+13 is not in (0, 3.6e+06] (milliseconds: at most an hour)"},
      {"keyframe beyond a year", R"([model]
path = "m.ply"
[glove]
backend = "sim"
[[glove.sim.script]]
finger = "index"
keyframes = [[0, 0, 0, 1], [1e308, 0, 0, 1]]
)",
       "glove.sim.script[0].keyframes[1]", 7, "time 1e+308 s is beyond a year (3.1536e+07 s)"},
      {"sim duration beyond a year", sim_scene("duration_s = 1e308"), "glove.sim.duration_s", 6,
       "out of range: 1e+308 is not in [0, 3.1536e+07] (seconds: at most a year)"},
      {"sim latency beyond an hour", sim_scene("latency_ms = 1e13"), "glove.sim.latency_ms", 6,
       "out of range: 1e+13 is not in [0, 3.6e+06]"},
      {"serial reconnect beyond an hour",
       "[model]\npath = \"m.ply\"\n[glove]\nbackend = \"serial\"\n[glove.serial]\ndevice = \"/dev/ttyS0\"\n"
       "reconnect_ms = 1e13\n",
       "glove.serial.reconnect_ms", 7, "out of range: 1e+13 is not in (0, 3.6e+06]"},
      // A script for a finger that does not act moves a fingertip nothing reads.
      {"script for a finger that does not act", R"([model]
path = "m.ply"
[glove]
backend = "sim"
fingers = ["thumb", "middle"]
[[glove.sim.script]]
finger = "middle"
keyframes = [[0, 0, 0, 1]]
[[glove.sim.script]]
finger = "index"
keyframes = [[0, 0, 0, 1]]
)",
       "glove.sim.script[1]", 10,
       "hand 0 finger 'index' does not act: glove.fingers is ['thumb', 'middle']; add it there or remove this script"},
      {"script for a hand that does not act", R"([model]
path = "m.ply"
[glove]
backend = "sim"
hands = [1]
[[glove.sim.script]]
hand = 1
finger = "index"
keyframes = [[0, 0, 0, 1]]
[[glove.sim.script]]
hand = 0
finger = 4
keyframes = [[0, 0, 0, 1]]
)",
       "glove.sim.script[1]", 11, "hand 0 finger 'little' does not act: glove.hands is [1]"},
      {"dropout of 1", sim_scene("dropout = 1.0"), "glove.sim.dropout", 6, "out of range: 1 is not in [0, 1)"},
      {"bad lcm url", kMinimal + "[lcm]\nurl = \"239.255.76.67\"\n", "lcm.url", 9, "is not an LCM URL"},
      // Each of these passed the scene and failed only once LCM was opened, on two lines (LCM's
      // own stderr, then ours) naming no key.
      {"lcm url, no such provider", kMinimal + "[lcm]\nurl = \"udp://239.255.76.67:7667\"\n", "lcm.url", 9,
       "'udp://239.255.76.67:7667' names no LCM provider (udpm, mpudpm, tcpq, memq or file)"},
      {"lcm url, not an address", kMinimal + "[lcm]\nurl = \"udpm://999.1.1.1:7667?ttl=0\"\n", "lcm.url", 9,
       "'udpm://999.1.1.1:7667?ttl=0' is not a usable LCM URL: '999.1.1.1' is not an IPv4 address"},
      {"lcm url, not multicast", kMinimal + "[lcm]\nurl = \"udpm://127.0.0.1:7667\"\n", "lcm.url", 9,
       "'127.0.0.1' is not a multicast address (224.0.0.0 to 239.255.255.255)"},
      {"lcm url, port", kMinimal + "[lcm]\nurl = \"udpm://239.255.76.67:70000\"\n", "lcm.url", 9,
       "port '70000' is not in 1..65535"},
      {"lcm url, ttl", kMinimal + "[lcm]\nurl = \"udpm://239.255.76.67:7667?ttl=x\"\n", "lcm.url", 9,
       "ttl 'x' is not in 0..255"},
      {"glove lcm url", "[model]\npath = \"m.ply\"\n[glove]\nbackend = \"lcm\"\n[glove.lcm]\nurl = \"file://\"\n",
       "glove.lcm.url", 6, "'file://' is not a usable LCM URL: names no file"},
      // A channel LCM cannot take passed too: every publish printed LCM's complaint and
      // delivered nothing, and a subscriber waited for samples that never came.
      {"glove lcm channel, too long",
       "[model]\npath = \"m.ply\"\n[glove]\nbackend = \"lcm\"\n[glove.lcm]\nchannel = \"" + std::string(64, 'G') +
           "\"\n",
       "glove.lcm.channel", 6, "is 64 bytes long; LCM takes at most 63"},
      {"haptic lcm channel, empty", kMinimal + "[haptic]\nsink = \"lcm\"\n[haptic.lcm]\nchannel = \"\"\n",
       "haptic.lcm.channel", 11, "must not be empty"},
  };
}

TEST(Scene, MalformedScenesNameTheirKeyAndLine) {
  const auto cases = malformed_scenes();
  ASSERT_GE(cases.size(), 20u);
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    try {
      parse(c.text);
      ADD_FAILURE() << "no error for: " << c.name;
    } catch (const SceneError& e) {
      const std::string message = e.what();
      EXPECT_EQ(e.key(), c.key) << message;
      EXPECT_EQ(e.line(), c.line) << message;
      EXPECT_EQ(e.file(), "t.toml");
      const std::string prefix = "t.toml:" + std::to_string(c.line) + ":";
      EXPECT_EQ(message.rfind(prefix, 0), 0u) << message;
      EXPECT_NE(message.find(": " + std::string(c.key) + ": "), std::string::npos) << message;
      EXPECT_NE(message.find(c.problem), std::string::npos) << message;
    }
  }
}

// Each time, timeout and rate past its upper bound, appended to kMinimal: refused on its own
// line (the last of the text), naming the key, with the bound printed by %g.
TEST(Scene, TimesTimeoutsAndRatesAreBoundedAbove) {
  struct Bound {
    std::string tables;  // appended to kMinimal; the bad key is on its last line
    const char* key;
    const char* problem;
  };
  const std::vector<Bound> bounds = {
      {"[haptic]\nsink = \"serial\"\n[haptic.serial]\ndevice = \"/dev/ttyS0\"\nreconnect_ms = 1e13\n",
       "haptic.serial.reconnect_ms", "out of range: 1e+13 is not in (0, 3.6e+06] (milliseconds: at most an hour)"},
      {"[filter]\nmin_cutoff = 1e9\n", "filter.min_cutoff", "out of range: 1e+09 is not in (0, 10000] (Hz)"},
      {"[filter]\nd_cutoff = 1e9\n", "filter.d_cutoff", "out of range: 1e+09 is not in (0, 10000] (Hz)"},
      {"[haptic]\nmax_force_rate = 1e300\n", "haptic.max_force_rate",
       "out of range: 1e+300 is not in (0, 1e+06] (N/s: 1000 N in a millisecond)"},
      {"[output]\nlog = \"x.lcmlog\"\nflush_interval_ms = 1e13\n", "output.flush_interval_ms",
       "out of range: 1e+13 is not in (0, 3.6e+06] (milliseconds: at most an hour)"},
      {"[output]\nlog = \"x.lcmlog\"\ntick_interval_ms = -1\n", "output.tick_interval_ms",
       "out of range: -1 is not in [0, 3.6e+06] (milliseconds: at most an hour)"},
  };
  for (const Bound& b : bounds) {
    SCOPED_TRACE(b.key);
    const int line = 7 + static_cast<int>(std::count(b.tables.begin(), b.tables.end(), '\n'));
    try {
      parse(kMinimal + b.tables);
      ADD_FAILURE() << "no error";
    } catch (const SceneError& e) {
      EXPECT_EQ(e.key(), b.key) << e.what();
      EXPECT_EQ(e.line(), line) << e.what();
      EXPECT_EQ(e.problem(), b.problem) << e.what();
    }
  }
  // At the bounds themselves, accepted.
  const Scene s = parse(kMinimal + "[filter]\nmin_cutoff = 1e4\n[haptic]\nmax_force_rate = 1e6\n");
  EXPECT_DOUBLE_EQ(s.filter.min_cutoff, 1e4);
  EXPECT_DOUBLE_EQ(s.haptic_limits.max_force_rate, 1e6);
}

// The glove source only reads: an OUT endpoint in its section would do nothing, so it is
// refused where it stands, saying where it belongs.
TEST(Scene, AGloveOutEndpointIsRefusedAndPointsToTheHapticSink) {
  try {
    parse(R"([model]
path = "m.ply"
[glove]
backend = "usb"
[glove.usb]
vendor_id = 0x1209
product_id = 0xA7C3
out_endpoint = 0x02
)");
    FAIL() << "no error";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.key(), "glove.usb.out_endpoint") << e.what();
    EXPECT_NE(e.problem().find("[haptic.usb] out_endpoint"), std::string::npos) << e.what();
  }
}

TEST(Scene, UnknownKeyMessageIsExact) {
  const std::string text = R"([model]
path = "m.ply"
[glove]
backend = "sim"
[glove.sim]
rate_hz = 80
seed = 3
jitter = 0.001
latency_ms = 2
repeat = false
duration_s = 3
ratee = 80
[[glove.sim.script]]
finger = "index"
keyframes = [[0, 0, 0, 1]]
)";
  try {
    parse_scene(text, "scenes/x.toml", "scenes");
    FAIL() << "no error";
  } catch (const SceneError& e) {
    EXPECT_STREQ(e.what(), "scenes/x.toml:12:1: glove.sim.ratee: unknown key");
    EXPECT_EQ(e.column(), 1);
  }
}

TEST(Scene, SyntaxErrorsUseTomlsPosition) {
  try {
    parse(kMinimal + "[loop]\nrate_hz = 1000\n  cpu = [1,\n");
    FAIL() << "no error";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.key(), "toml");
    EXPECT_GE(e.line(), 10);
    EXPECT_GT(e.column(), 0);
  }
}

}  // namespace
}  // namespace sculpt::rt

namespace sculpt::rt {
namespace {

TEST(Scene, RealtimeIsOffTryOrRequire) {
  EXPECT_EQ(parse(kMinimal + "[loop]\nrealtime = false\n").loop.realtime, RealtimeMode::kOff);
  EXPECT_EQ(parse(kMinimal + "[loop]\nrealtime = \"try\"\n").loop.realtime, RealtimeMode::kTry);
  EXPECT_EQ(parse(kMinimal + "[loop]\nrealtime = \"require\"\n").loop.realtime, RealtimeMode::kRequire);
  try {
    parse(kMinimal + "[loop]\nrealtime = \"always\"\n");
    FAIL() << "an unknown mode must be refused";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("realtime"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("require"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace sculpt::rt
