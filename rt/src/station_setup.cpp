#include "sculpt/rt/station_setup.hpp"

#include <cstdio>
#include <stdexcept>

#include "sculpt/base/number_text.hpp"
#include "sculpt/deform/model_io.hpp"
#include "sculpt/deform/model_scale.hpp"
#include "sculpt/deform/normal_check.hpp"
#include "sculpt/deform/normals.hpp"
#include "sculpt/deform/region.hpp"
#include "sculpt/deform/settings_range.hpp"
#include "sculpt/hal/backend_factory.hpp"
#include "sculpt/rt/reduced_model.hpp"

namespace sculpt::rt {
namespace {

// The spacing and its statistic are printed once beside the model; each note refers to them.
std::string describe(const char* key, double value, double factor) {
  char buffer[160];
  std::snprintf(buffer, sizeof buffer, "%s = %.4g (%g x the model's spacing)", key, value, factor);
  return buffer;
}

// "from faces", and what their winding needed, so that a rewound export is never silent.
std::string from_faces(const deform::FaceOrientation& wound, const deform::PointModel& m) {
  std::string text = "from faces";
  if (wound.turned > 0) {
    text += " (" + std::to_string(wound.turned) + " of " + std::to_string(m.triangles.size() / 3) +
            " rewound to agree with their neighbours)";
  }
  if (wound.conflicts > 0) text += " (" + std::to_string(wound.conflicts) + " edges with no consistent winding)";
  return text;
}

void load_normals(StationSetup& s, const Scene& scene) {
  deform::PointModel& m = s.model;
  switch (scene.model.normals) {
    case NormalsSource::kNone:
      m.clear_normals();
      s.normals_source = "none";
      return;
    case NormalsSource::kFaces:
      if (m.triangles.empty()) {
        throw std::invalid_argument("model.normals = \"faces\" but " + scene.model.path + " has no faces");
      }
      s.normals_source = from_faces(deform::compute_normals_from_faces(m), m);
      return;
    case NormalsSource::kPca:
      deform::estimate_normals(m);
      s.normals_source = "estimated (PCA)";
      return;
    case NormalsSource::kAuto:
      if (m.has_normals()) {
        s.normal_report = deform::check_normals(m, scene.model.bad_normals, scene.model.path);
        const std::string changed = deform::describe(s.normal_report);
        s.normals_source = changed.empty() ? "file" : "file (" + changed + ")";
        return;
      }
      if (m.triangles.empty()) {
        deform::estimate_normals(m);
        s.normals_source = "estimated (PCA)";
      } else {
        s.normals_source = from_faces(deform::compute_normals_from_faces(m), m);
      }
      return;
  }
}

// The scene's lengths were checked for sign and finiteness when it was read; against the model
// they can be checked only once it is loaded. Messages name the scene key and the scene file.
void check_against_model(const StationSetup& s, const Scene& scene) {
  try {
    deform::SettingNames names;
    names.bc_radius = "deform.bc_radius";
    names.min_source_distance = "deform.delta_d";
    names.guard_distance = "deform.delta_r";
    names.regularization = "kernel.eps";
    deform::check_settings_against_model(s.settings.deform, s.model, names);
    const deform::ModelExtent extent = deform::ModelExtent::of(s.model);
    deform::check_length_against_model("deform.delta_s", s.settings.delta_s, deform::LengthRule::kNonNegative, extent);
    if (s.settings.region.kind == RegionPolicy::Kind::kRadius) {
      deform::check_length_against_model("heuristic.region", s.settings.region.radius, deform::LengthRule::kPositive,
                                         extent);
      // Else refused only by the deformer, without the key, once the station is built.
      const double floor =
          deform::smallest_region_radius(s.settings.deform.region, s.settings.deform.contact.bc_radius);
      if (!(s.settings.region.radius > floor)) {
        throw std::invalid_argument("heuristic.region: radius " + base::number_text(s.settings.region.radius) +
                                    " must exceed deform.bc_radius plus the region's border width (" +
                                    base::number_text(floor) + ")");
      }
    }
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(scene.file + ": " + e.what());
  }
}

}  // namespace

StationSetup prepare_station(const Scene& scene) {
  StationSetup s;
  s.model = deform::read_model(scene.model.path);
  load_normals(s, scene);
  if (scene.heuristic.reduced_ratio < 1.0) {
    // Thesis 4.4.1: sculpt a uniform-density subsample interactively; the log's collision events
    // then apply to the full model offline (sculpt replay).
    const std::size_t full = s.model.size();
    s.full_model = deform::model_identity(s.model);
    s.model = reduced_model(s.model, scene.heuristic.reduced_ratio);
    s.notes.push_back("reduced model set: " + std::to_string(s.model.size()) + " of " + std::to_string(full) +
                      " points (heuristic.reduced_ratio)");
  }
  try {
    s.spacing = deform::typical_spacing(s.model, deform::PointIndex(s.model));
  } catch (const std::invalid_argument& e) {
    // A reduced set too small to have a length is the scene's ratio; otherwise it is the model
    // file's, named as a bad file is (exit 1), not as an unnamed argument.
    if (!s.full_model) throw deform::ModelFileError(scene.model.path, "", e.what());
    throw std::invalid_argument(
        scene.file + ": heuristic.reduced_ratio = " + base::number_text(scene.heuristic.reduced_ratio) + " leaves " +
        std::to_string(s.model.size()) + " of " + std::to_string(s.full_model->points) + " points: " + e.what());
  }

  StationSettings& st = s.settings;
  st.rate_hz = scene.loop.rate_hz;
  st.haptic = scene.haptic_limits;
  st.glove_timeout_s = scene.glove.timeout_ms * 1e-3;
  for (std::uint8_t hand : scene.glove.hands) {
    for (std::uint8_t finger : scene.glove.fingers) st.fingers.push_back({hand, finger});
  }
  st.filter_enabled = scene.filter.enabled;
  st.filter = {scene.filter.min_cutoff, scene.filter.beta, scene.filter.d_cutoff};
  if (scene.glove.config.backend == hal::Backend::kSim) st.glove_rate_hz = scene.glove.config.sim.rate_hz;

  // Distances the thesis gave in its sphere's units are derived from this model's spacing
  // unless the scene sets them (the thesis's sphere has a spacing of about 0.06).
  const auto pick = [&](const std::optional<double>& given, double factor, const char* key) {
    if (given) return *given;
    const double value = factor * s.spacing.value;
    s.notes.push_back(describe(key, value, factor));
    return value;
  };
  deform::DeformSettings& d = st.deform;
  d.kernel = {scene.kernel.kind, scene.material, scene.kernel.eps};
  d.contact.mode = scene.deform.mode;
  d.contact.bc_radius = pick(scene.deform.bc_radius, 1.0, "deform.bc_radius");
  d.contact.min_source_distance = pick(scene.deform.delta_d, 0.25, "deform.delta_d");
  d.contact.guard_distance = pick(scene.deform.delta_r, 1.5, "deform.delta_r");
  d.contact.reference = scene.model.reference;
  d.contact.max_patch_points = scene.deform.max_patch_points;
  st.delta_s = pick(scene.deform.delta_s, 1.0, "deform.delta_s");
  d.solver.form = scene.deform.form;
  d.field.precision = scene.deform.precision;
  d.threads = scene.deform.threads;
  d.field.carry_normals = scene.deform.carry_normals;
  d.field.normal_skip_bound = scene.deform.normal_skip_bound;
  d.field.fast_inverse_sqrt = scene.deform.fast_inverse_sqrt;
  d.region.border_weight = scene.deform.border_weight;
  d.region.global_when_cheaper = !scene.heuristic.strict_region;
  switch (scene.heuristic.region) {
    case RegionChoice::kGlobal: st.region.kind = RegionPolicy::Kind::kGlobal; break;
    case RegionChoice::kRadius: st.region.kind = RegionPolicy::Kind::kRadius; break;
    case RegionChoice::kAuto: st.region.kind = RegionPolicy::Kind::kAuto; break;
  }
  st.region.radius = scene.heuristic.region_radius;
  st.region.budget_fraction = scene.heuristic.budget_fraction;
  check_against_model(s, scene);

  if (!scene.registration.landmarks.empty()) {
    std::vector<std::array<double, 3>> glove, model;
    for (const Landmark& l : scene.registration.landmarks) {
      glove.push_back({l.glove.x, l.glove.y, l.glove.z});
      model.push_back({l.model.x, l.model.y, l.model.z});
    }
    s.calibration = calibrate_umeyama(glove, model);
    st.registration = s.calibration->transform;
  } else {
    const auto& q = scene.registration.rotation;
    st.registration = SimilarityTransform::from_scale_rotation_translation(
        scene.registration.scale, Quaternion{q[0], q[1], q[2], q[3]},
        {scene.registration.translation.x, scene.registration.translation.y, scene.registration.translation.z});
  }
  if (scene.hand.bone_lengths) {
    std::array<hal::FingerBones, hal::kFingers> bones = hal::HandModel().bones();
    for (std::size_t f = 0; f < hal::kFingers; ++f) {
      bones[f].proximal = static_cast<float>((*scene.hand.bone_lengths)[f][0]);
      bones[f].middle = static_cast<float>((*scene.hand.bone_lengths)[f][1]);
      bones[f].distal = static_cast<float>((*scene.hand.bone_lengths)[f][2]);
    }
    st.hand_model = hal::HandModel(bones);
  }
  return s;
}

std::unique_ptr<Station> make_station(StationSetup& setup, const Scene& scene) {
  return std::make_unique<Station>(setup.model, setup.settings, hal::make_glove_source(scene.glove.config),
                                   hal::make_haptic_sink(scene.haptic));
}

}  // namespace sculpt::rt
