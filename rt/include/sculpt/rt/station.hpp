#pragma once
// The station's work for one tick of the loop (ARCHITECTURE.md steps 1-8): newest glove
// sample per hand -> fingertips -> One-Euro filter -> Δs dead band -> registration into the
// model frame -> collision frame within the budget -> haptic forces -> accounting.

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "sculpt/deform/deformer.hpp"
#include "sculpt/hal/glove_source.hpp"
#include "sculpt/hal/hand_model.hpp"
#include "sculpt/hal/haptic_sink.hpp"
#include "sculpt/rt/dead_band.hpp"
#include "sculpt/rt/haptic_shaper.hpp"
#include "sculpt/rt/index_rebuilder.hpp"
#include "sculpt/rt/latency_histogram.hpp"
#include "sculpt/rt/one_euro_filter.hpp"
#include "sculpt/rt/region_sizer.hpp"
#include "sculpt/rt/similarity_transform.hpp"
#include "sculpt/rt/station_recorder.hpp"

namespace sculpt::rt {

struct FingerId {
  std::uint8_t hand = 0;
  std::uint8_t finger = 1;
};

/// How large a region a collision frame may move.
struct RegionPolicy {
  enum class Kind { kGlobal, kRadius, kAuto } kind = Kind::kAuto;
  double radius = 0.0;           ///< kRadius: fixed; kAuto: the first frame's radius (0: 10 spacings)
  double budget_fraction = 0.6;  ///< kAuto: share of the tick the deformation may use
};

struct StationSettings {
  double rate_hz = 1000.0;
  double glove_timeout_s = 0.1;   ///< older newest-sample than this: stale, every force released
  std::vector<FingerId> fingers;  ///< the fingers that act, at most deform::kMaxSources
  bool filter_enabled = true;
  OneEuroParams filter;
  double glove_rate_hz = 80.0;  ///< nominal sample rate, for the filter's first step
  double delta_s = 0.0;         ///< Δs dead band, model units (applied after registration)
  SimilarityTransform registration;
  hal::HandModel hand_model;
  RegionPolicy region;
  deform::DeformSettings deform;  ///< its region is set from `region`
  HapticLimits haptic;            ///< what may reach the actuators
};

/// Per finger, what the last tick saw.
struct FingerState {
  bool tracked = false;     ///< the glove has reported this finger
  deform::Vec3 raw;         ///< glove frame
  deform::Vec3 filtered;    ///< glove frame
  deform::Vec3 registered;  ///< model frame
  bool in_contact = false;
  /// Glove frame, newtons: the surface's reaction on the finger over the stroke so far (by
  /// superposition, the sum of its frames' traction resultants), held while in contact.
  deform::Vec3 reaction;
  deform::Vec3 haptic_force;     ///< glove frame, newtons: what was last sent (gain, clamp, slew)
  std::uint64_t collisions = 0;  ///< total collision events of this finger
};

enum class GloveState : std::uint8_t { kWaiting, kLive, kStale };

struct TickReport {
  std::uint64_t tick = 0;
  GloveState glove = GloveState::kWaiting;
  double glove_age_ms = 0.0;
  std::size_t samples = 0;  ///< glove samples taken this tick
  bool frame = false;       ///< a collision frame ran
  std::size_t collisions = 0;
  std::size_t region_points = 0;
  double region_radius = 0.0;
  double deform_ns = 0.0;
  std::int64_t budget_ns = 0;
  double min_jacobian = 1.0;       ///< of this tick's frame (1 without one)
  deform::GuardCounts guards;      ///< the stability guards that acted this tick
  std::uint64_t out_of_range = 0;  ///< fingertips dropped so far (cumulative, as in the totals)
};

/// Totals since start, for the summary.
struct StationTotals {
  std::uint64_t ticks = 0;
  std::uint64_t frames = 0;
  std::uint64_t collisions = 0;
  std::uint64_t stale_ticks = 0;
  std::uint64_t stale_events = 0;  ///< times a hand went stale (each hand counts on its own)
  std::uint64_t samples = 0;
  /// Samples a newer one of the same hand replaced within the tick that took both (the loop acts
  /// on a hand's newest sample): a glove faster than the loop, or a tick held up.
  std::uint64_t superseded_samples = 0;
  double max_region_radius = 0.0;
  std::size_t max_region_points = 0;
  std::uint64_t index_rebuilds = 0;  ///< k-d trees rebuilt in the background and installed
  /// Wall time of the deformation in each frame with a collision (ns), the part of a tick that
  /// grows with the model and the region. Beside the loop's tick time it tells a slow frame
  /// from a tick the machine held up: on these VMs the hypervisor reports no steal time, so a
  /// preempted tick grows on the thread's CPU clock too.
  LatencyHistogram collision_frame_time;
  deform::GuardCounts guards;  ///< every stability guard that acted, summed
  /// Dropped: fingertips not finite or far outside the model, and glove samples holding an inf
  /// or NaN anywhere (neither logged nor taken).
  std::uint64_t out_of_range = 0;
  /// Strokes whose summed reaction stopped being finite: the finger's force is released (the
  /// safe state), its sum restarted, and the station goes on. Never expected; counted if it is.
  std::uint64_t haptic_faults = 0;
  /// Per hand: ticks it was in contact, and commands its haptic sink took in those ticks (a
  /// command every such tick is the promise; a full queue or a dead link shows as fewer).
  std::array<std::uint64_t, hal::kHands> contact_ticks{};
  std::array<std::uint64_t, hal::kHands> contact_commands{};
};

/// Everything is allocated by the constructor; tick() allocates nothing, throws nothing and
/// prints nothing. The glove source and haptic sink are started by start() (set-up).
class Station {
 public:
  Station(deform::PointModel& model, StationSettings settings, std::unique_ptr<hal::GloveSource> glove,
          std::unique_ptr<hal::HapticSink> haptic);
  ~Station();

  void start();
  void stop();
  /// Reports samples, fingertips, frames and haptic commands to `recorder` (set-up; may be null).
  void set_recorder(StationRecorder* recorder) { recorder_ = recorder; }
  /// Replay: the step whose first frame has id k uses radii[k] as its region radius instead of
  /// sizing it to the budget (0: no recorded radius), so a re-run reproduces the recorded
  /// session exactly. The span must outlive the station.
  void set_region_schedule(std::span<const double> radii) { region_schedule_ = radii; }

  /// One tick at time `now_ns` (CLOCK_MONOTONIC) with `budget_ns` of the period left.
  const TickReport& tick(std::int64_t now_ns, std::int64_t budget_ns) noexcept;

  const std::vector<FingerState>& fingers() const { return fingers_; }
  const StationSettings& settings() const { return settings_; }
  const StationTotals& totals() const { return totals_; }
  /// The id the next collision frame will carry: ids count every frame the deformer ran, a
  /// split step's frames each, as the log records them.
  std::int64_t next_frame_id() const noexcept { return frame_id_; }
  /// The last collision frame's report (an empty report before the first frame).
  const deform::FrameReport& last_frame() const { return *last_frame_; }
  hal::SourceCounters glove_counters() const { return glove_->counters(); }
  hal::SourceState glove_state() const { return glove_->state(); }
  const hal::HapticSink* haptic() const { return haptic_.get(); }
  deform::Deformer& deformer() { return deformer_; }

 private:
  struct Track {
    OneEuroFilter3 filter;
    DeadBand dead_band;
    bool accepted_this_tick = false;
  };

  void take_samples(std::int64_t now_ns) noexcept;
  /// Releases every force of the fingers of `hand` and forgets their history (one zero command).
  void release_forces(std::uint8_t hand) noexcept;
  void update_fingers(std::int64_t now_ns) noexcept;
  void run_frame(std::int64_t budget_ns) noexcept;
  /// Every tick: a command per hand while a finger of it is in contact, one zero command when
  /// the last one lets go, and a heartbeat every limits.heartbeat_s otherwise.
  void send_haptics() noexcept;
  void size_region(std::int64_t budget_ns) noexcept;
  deform::Vec3 to_glove_frame(const deform::Vec3& v) const noexcept;

  StationSettings settings_;
  deform::Deformer deformer_;
  std::unique_ptr<hal::GloveSource> glove_;
  std::unique_ptr<hal::HapticSink> haptic_;
  std::vector<hal::GloveSample> inbox_;
  std::array<hal::GloveSample, hal::kHands> newest_{};
  std::array<bool, hal::kHands> has_sample_{};
  std::array<bool, hal::kHands> fresh_{};
  std::array<std::int64_t, hal::kHands> last_sample_ns_{};  // newest sample's receive time, per hand
  std::array<bool, hal::kHands> stale_{};                   // the hand is silent past the timeout
  std::array<bool, hal::kHands> acting_hand_{};             // a finger of this hand acts
  std::vector<FingerState> fingers_;
  std::vector<Track> tracks_;
  std::vector<deform::ProbeMotion> probes_;
  std::vector<std::size_t> probe_finger_;  // probes_[k] belongs to fingers_[probe_finger_[k]]
  TickReport report_;
  StationTotals totals_;
  deform::FrameReport empty_frame_;
  const deform::FrameReport* last_frame_ = &empty_frame_;
  RegionSizer region_sizer_;  // kAuto: the next frame's radius from the frames' times
  HapticShaper shaper_;
  std::array<bool, hal::kHands> hand_touching_{};  // a finger of the hand was in contact last tick
  std::array<std::int64_t, hal::kHands> last_command_ns_{};
  double newtons_per_model_area_ = 1.0;  // (metres per model unit)^2
  IndexRebuilder rebuilder_;
  StationRecorder* recorder_ = nullptr;
  std::span<const double> region_schedule_;
  std::int64_t first_tick_ns_ = -1;
  std::int64_t now_ns_ = 0;
  std::int64_t frame_id_ = 0;
  std::vector<FingerId> probe_ids_;                   // the finger of each probe, for the recorder
  std::array<bool, deform::kMaxSources> accepted_{};  // per finger, this tick
  double rebuild_drift_;                              // ask for a new tree once the drift passes this
};

}  // namespace sculpt::rt
