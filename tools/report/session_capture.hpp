#pragma once
// A scene's simulated session, recorded in virtual time: the scene's scripted glove through the
// whole station (filter, dead band, registration, deformer), so that the steps the report
// measures are the ones `sculpt run` would have taken, on any machine, at any speed.

#include <cstdint>
#include <vector>

#include "sculpt/deform/deformer.hpp"
#include "sculpt/hal/glove_sample.hpp"
#include "sculpt/logging/records.hpp"
#include "sculpt/rt/replay_glove_source.hpp"
#include "sculpt/rt/scene.hpp"

namespace sculpt::tools::report {

struct RecordedSession {
  /// The probes of every step that applied a frame, in order: what the exact session replays.
  std::vector<std::vector<deform::ProbeMotion>> steps;
  /// Per step, the region radius the session's deformer had in force (0 for a global region):
  /// with heuristic.region = "auto", what the tick's budget allowed on this machine.
  std::vector<double> step_radius;
  std::vector<std::uint64_t> step_tick;  ///< the station's tick of each step
  /// Every applied frame as the log records it: what a reduced session transfers.
  std::vector<logging::CollisionRecord> records;
  /// The deformer's time of each step that collided, ns (the station measures it).
  std::vector<double> frame_ns;
  deform::GuardCounts guards;       ///< every guard the station's deformer applied, summed
  deform::PointModel initial;       ///< the model as loaded (reduced when the scene asks)
  deform::PointModel final_model;   ///< as the session left it
  deform::DeformSettings settings;  ///< the deformer's settings at the start
  double spacing = 0.0;             ///< the model's typical spacing, model units
};

/// Runs `scene` on `samples` (a logged session's), or when that is null on the samples of its
/// simulated glove's script, to their end plus the glove's timeout, and returns what it did.
/// Throws std::invalid_argument for a scene without samples of either kind, and whatever the
/// station's set-up throws.
RecordedSession record_session(const rt::Scene& scene, const rt::SampleLog* samples = nullptr);

/// The trajectory the report measures: the session's steps taken with a global region, so that
/// which steps apply a frame cannot depend on this machine's speed (an auto region is sized by
/// the measured frame time, and a region can decide whether a frame folds); each step carries
/// the radius `as_run` (the session as its scene asks) had in force at that tick, for the
/// "region auto" row.
RecordedSession record_trajectory(const rt::Scene& scene, const rt::SampleLog* samples, const RecordedSession& as_run);

}  // namespace sculpt::tools::report
