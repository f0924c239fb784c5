#pragma once
// The scene file: one TOML document that names everything a sculpting session runs (model,
// material, kernel, heuristics, glove, hand, filter, registration, haptics, loop, LCM,
// outputs). docs/scene.md documents every key. The parser is strict because a scene is the
// only configuration the station has: a typo must stop it at start-up with the key and the
// line, not run with a silent default.
//
// toml++ stays inside scene.cpp: this header only holds plain data.

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "sculpt/deform/contact.hpp"
#include "sculpt/deform/displacement_field.hpp"
#include "sculpt/deform/kernel.hpp"
#include "sculpt/deform/normal_check.hpp"
#include "sculpt/deform/vec3.hpp"
#include "sculpt/deform/weight_solver.hpp"
#include "sculpt/hal/backend_config.hpp"
#include "sculpt/hal/glove_sample.hpp"
#include "sculpt/rt/haptic_shaper.hpp"

namespace sculpt::rt {

/// A scene that cannot be used. what() is "<file>:<line>:<column>: <key>: <problem>", with
/// <key> the full dotted key ("glove.sim.rate_hz", "glove.sim.script[1].keyframes[2]"), or
/// "toml" for a syntax error, or "file" when the file cannot be read (then without a position).
class SceneError : public std::runtime_error {
 public:
  SceneError(std::string file, int line, int column, std::string key, std::string problem);

  const std::string& file() const { return file_; }
  int line() const { return line_; }      ///< 1-based; 0 when there is no position
  int column() const { return column_; }  ///< 1-based; 0 when there is no position
  const std::string& key() const { return key_; }
  const std::string& problem() const { return problem_; }

 private:
  std::string file_;
  int line_;
  int column_;
  std::string key_;
  std::string problem_;
};

/// Where the model's normals come from (they decide inside from outside, and carry traction).
enum class NormalsSource {
  kAuto,   ///< the file's normals, else from its faces, else PCA
  kFaces,  ///< from the file's faces (area-weighted); the file must have faces
  kPca,    ///< PCA over neighbours with consistent orientation
  kNone,   ///< no normals: the inside is told by model.reference (thesis's reference point)
};

struct ModelScene {
  std::string path;  ///< resolved against the scene file's directory
  /// A point known to be outside (the scanner); set exactly when normals == kNone.
  std::optional<deform::Vec3> reference;
  NormalsSource normals = NormalsSource::kAuto;
  /// What the file's zero or non-finite normals get when its normals are used (normals = auto).
  deform::NormalPolicy bad_normals = deform::NormalPolicy::kReestimate;
};

struct KernelScene {
  deform::KernelKind kind = deform::KernelKind::kKelvin;
  double eps = 0.0;  ///< regularization radius (model units); > 0 exactly for kRegularized
};

/// The thesis's offsets. Unset ones are derived from the model's mean point spacing when the
/// model is loaded (bc_radius = 1, delta_s = 1, delta_d = 0.25, delta_r = 1.5 spacings), since
/// scans differ in scale by three orders of magnitude.
struct DeformScene {
  deform::WeightForm form = deform::WeightForm::kForce;
  deform::ContactMode mode = deform::ContactMode::kPush;
  std::optional<double> bc_radius;  ///< eps: points this close to the contact follow the probe
  std::optional<double> delta_s;    ///< dead band: smaller fingertip moves are ignored
  std::optional<double> delta_d;    ///< a source never sits closer than this to the contact
  std::optional<double> delta_r;    ///< a free finger this close to the surface pins it
  deform::Precision precision = deform::Precision::kFloat;
  bool carry_normals = true;
  double normal_skip_bound = 0.0;       ///< the bounded normal update (0: off; FieldOptions)
  bool fast_inverse_sqrt = false;       ///< 1/r from the processor's estimate (FieldOptions)
  double border_weight = 1.0;           ///< weight of the region's pinned band (localised regions only)
  std::size_t max_patch_points = 1024;  ///< boundary-condition points per finger's patch, thinned beyond
  int threads = 1;                      ///< 2: the displacement loop's worker on the second core
};

enum class RegionChoice {
  kGlobal,  ///< every point moves
  kAuto,    ///< the radius the tick budget allows, nearest points first
  kRadius,  ///< a fixed radius around each contact
};

struct HeuristicScene {
  RegionChoice region = RegionChoice::kGlobal;
  double region_radius = 0.0;    ///< model units, for kRadius
  double budget_fraction = 0.6;  ///< share of the tick the deformation may use, (0, 1]
  double reduced_ratio = 1.0;    ///< (0, 1]: record on this fraction of the points (thesis 4.4.1)
  /// Only the region's points move, even in a frame whose region holds so much of the model
  /// that the global frame would cost less (deform::RegionSettings::global_when_cheaper).
  bool strict_region = false;
};

struct GloveScene {
  hal::GloveConfig config;            ///< backend and its settings; only the chosen backend's are read
  double timeout_ms = 100.0;          ///< a hand with no sample for this long is stale: forces released
  std::vector<std::uint8_t> hands;    ///< hands that act (0, 1), ascending
  std::vector<std::uint8_t> fingers;  ///< fingers that act (0 thumb .. 4 little), ascending
};

struct HandScene {
  hal::SampleKind kind = hal::SampleKind::kPositions;
  /// Per finger (thumb .. little), its three segment lengths from the MCP (thumb: CMC)
  /// joint outward, glove units. Only for kAngles; unset means the hand model's defaults.
  std::optional<std::array<std::array<double, 3>, hal::kFingers>> bone_lengths;
};

/// One Euro filter (Casiez et al. 2012) on each fingertip coordinate.
struct FilterScene {
  bool enabled = true;
  double min_cutoff = 1.0;  ///< Hz
  double beta = 0.1;        ///< cutoff slope, per (glove unit / s)
  double d_cutoff = 1.0;    ///< Hz, for the derivative
};

struct Landmark {
  deform::Vec3 glove;  ///< glove frame
  deform::Vec3 model;  ///< model frame
};

/// Glove frame -> model frame: model = scale * R * glove + translation. Either the explicit
/// transform, or (landmarks non-empty) a similarity fitted to the landmarks at start-up.
struct RegistrationScene {
  double scale = 1.0;
  std::array<double, 4> rotation{1.0, 0.0, 0.0, 0.0};  ///< unit quaternion w, x, y, z
  deform::Vec3 translation;
  std::vector<Landmark> landmarks;  ///< empty, or at least 3 not on one line
};

/// loop.realtime: `false` asks for nothing; "try" (or `true`) asks for SCHED_FIFO and runs
/// anyway when refused; "require" asks for SCHED_FIFO and mlockall and refuses to start
/// without them, so a station believed real-time is.
enum class RealtimeMode { kOff, kTry, kRequire };

struct LoopScene {
  double rate_hz = 1000.0;  ///< 50 .. 2000
  RealtimeMode realtime = RealtimeMode::kOff;
  bool lock_memory = false;  ///< mlockall
  int cpu = -1;              ///< pin the loop thread to this CPU; -1 none
};

struct LcmScene {
  std::string url = "udpm://239.255.76.67:7667?ttl=0";
  bool publish = false;  ///< live-publish ticks and events
};

struct OutputScene {
  std::optional<std::string> model;  ///< final PLY (or .xyz), resolved
  std::optional<std::string> log;    ///< durable event log (LCM log format), resolved
  std::optional<std::string> json;   ///< summary, resolved
  double flush_interval_ms = 100.0;  ///< how often the log is flushed to disk
  /// The log keeps every eventful tick and a quiet one at least this often (0: every tick;
  /// TickLogFilter).
  double tick_interval_ms = 100.0;
};

struct Scene {
  std::string file;      ///< the scene file as given (for messages)
  std::string base_dir;  ///< relative paths were resolved against this
  std::string text;      ///< the TOML text it was parsed from (the session header records it)
  ModelScene model;
  deform::Material material;
  KernelScene kernel;
  DeformScene deform;
  HeuristicScene heuristic;
  GloveScene glove;
  HandScene hand;
  FilterScene filter;
  RegistrationScene registration;
  hal::HapticConfig haptic;
  HapticLimits haptic_limits;  ///< [haptic] gain, max_force (N), max_force_rate (N/s)
  LoopScene loop;
  LcmScene lcm;
  OutputScene output;
};

/// Reads and parses a scene file; relative paths resolve against its directory.
/// @throw SceneError for an unreadable file or any problem parse_scene reports.
Scene load_scene(const std::string& path);

/// Parses scene text. `path_for_errors` names the file in messages; relative paths resolve
/// against `base_dir`. Checks every key, type, range and combination that does not need the
/// model itself; the model file is read (and its spacing found) when the station starts.
/// @throw SceneError naming the first problem found.
Scene parse_scene(std::string_view text, const std::string& path_for_errors, const std::string& base_dir);

}  // namespace sculpt::rt
