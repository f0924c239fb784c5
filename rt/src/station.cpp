#include "sculpt/rt/station.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "sculpt/deform/model_scale.hpp"
#include "sculpt/rt/fixed_rate_loop.hpp"

namespace sculpt::rt {
namespace {

deform::Vec3 to_vec3(const std::array<double, 3>& a) { return {a[0], a[1], a[2]}; }
std::array<double, 3> to_array(const deform::Vec3& v) { return {v.x, v.y, v.z}; }

// The deformer's settings follow from the station's: one probe per acting finger, traction
// only when a haptic sink will use it, and the region from the policy.
deform::DeformSettings prepared(StationSettings& s, const deform::PointModel& model, bool haptics) {
  if (s.fingers.empty()) throw std::invalid_argument("station: no finger acts (glove.fingers is empty)");
  if (s.fingers.size() > deform::kMaxSources) {
    throw std::invalid_argument("station: at most " + std::to_string(deform::kMaxSources) + " fingers can act");
  }
  for (std::size_t i = 0; i < s.fingers.size(); ++i) {
    const FingerId f = s.fingers[i];
    if (f.hand >= hal::kHands || f.finger >= hal::kFingers) {
      throw std::invalid_argument("station: finger " + std::to_string(i) + " is not hand 0-1, finger 0-4");
    }
    for (std::size_t j = 0; j < i; ++j) {
      if (s.fingers[j].hand == f.hand && s.fingers[j].finger == f.finger) {
        throw std::invalid_argument("station: finger " + std::to_string(i) + " is listed twice");
      }
    }
  }
  if (!(s.glove_timeout_s > 0.0)) throw std::invalid_argument("station: glove timeout must be positive");
  deform::DeformSettings d = s.deform;
  d.max_probes = s.fingers.size();
  d.traction = haptics;
  d.measure_extremes = false;  // a report's diagnostic: nothing in the station reads it
  switch (s.region.kind) {
    case RegionPolicy::Kind::kGlobal: d.region.kind = deform::RegionSettings::Kind::kGlobal; break;
    case RegionPolicy::Kind::kRadius:
      d.region.kind = deform::RegionSettings::Kind::kRadius;
      d.region.radius = s.region.radius;
      break;
    case RegionPolicy::Kind::kAuto: {
      d.region.kind = deform::RegionSettings::Kind::kRadius;
      const double spacing = deform::typical_spacing(model, deform::PointIndex(model)).value;
      const double floor = 1.5 * (d.contact.bc_radius + std::max(d.region.border_width, d.contact.bc_radius));
      d.region.radius = std::max(s.region.radius > 0.0 ? s.region.radius : 10.0 * spacing, floor);
      if (!(s.region.budget_fraction > 0.0 && s.region.budget_fraction <= 1.0)) {
        throw std::invalid_argument("station: budget fraction must lie in (0, 1]");
      }
      break;
    }
  }
  return d;
}

}  // namespace

Station::Station(deform::PointModel& model, StationSettings settings, std::unique_ptr<hal::GloveSource> glove,
                 std::unique_ptr<hal::HapticSink> haptic)
    : settings_(std::move(settings)),
      deformer_(model, prepared(settings_, model, haptic != nullptr)),
      glove_(std::move(glove)),
      haptic_(std::move(haptic)),
      region_sizer_(settings_.region.budget_fraction),
      shaper_(settings_.haptic, settings_.fingers.size(), settings_.rate_hz),
      rebuilder_(model.size()),
      // Queries widen by the drift: past half the contact radius their candidate sets grow.
      rebuild_drift_(0.5 * deformer_.settings().contact.bc_radius) {
  if (!glove_) throw std::invalid_argument("station: no glove source");
  inbox_.resize(256);
  // Traction is in units of G (pascals) and the resultant sums it over model-unit areas; the
  // registration maps glove metres to model units with scale s, so a model unit is 1/s metres.
  const double metres_per_unit = 1.0 / settings_.registration.scale();
  newtons_per_model_area_ = metres_per_unit * metres_per_unit;
  for (const FingerId f : settings_.fingers) acting_hand_[f.hand] = true;
  fingers_.resize(settings_.fingers.size());
  tracks_.reserve(settings_.fingers.size());
  for (std::size_t i = 0; i < settings_.fingers.size(); ++i) {
    tracks_.push_back(
        Track{OneEuroFilter3(settings_.filter, settings_.glove_rate_hz), DeadBand(settings_.delta_s), false});
  }
  probes_.reserve(settings_.fingers.size());
  probe_finger_.reserve(settings_.fingers.size());
  probe_ids_.reserve(settings_.fingers.size());
}

Station::~Station() { stop(); }

void Station::start() {
  if (haptic_) haptic_->start();
  glove_->start();
}

void Station::stop() {
  glove_->stop();
  if (haptic_) haptic_->stop();
}

void Station::take_samples(std::int64_t now_ns) noexcept {
  fresh_.fill(false);
  std::size_t n = 0;
  // Drain everything queued: the newest sample per hand wins, older ones only count.
  while ((n = glove_->poll(inbox_)) > 0) {
    for (std::size_t i = 0; i < n; ++i) {
      const hal::GloveSample& s = inbox_[i];
      if (s.hand >= hal::kHands) continue;
      // An inf or NaN anywhere makes the sample unusable, as the LCM decoder already rules: it
      // is counted and neither logged nor taken, so it keeps no hand alive and the log (which
      // replay refuses such a sample from) stays the session's exact history.
      if (!hal::all_finite(s)) {
        ++totals_.out_of_range;
        continue;
      }
      if (fresh_[s.hand]) ++totals_.superseded_samples;
      newest_[s.hand] = s;
      ++report_.samples;
      if (recorder_) recorder_->glove_sample(s);
      has_sample_[s.hand] = true;
      fresh_[s.hand] = true;
      last_sample_ns_[s.hand] = std::max(last_sample_ns_[s.hand], s.receive_time_ns);
    }
    if (n < inbox_.size()) break;
  }
  totals_.samples += report_.samples;
  // The age that matters is the oldest among the acting hands that have reported.
  double age_ns = 0.0;
  for (std::uint8_t h = 0; h < hal::kHands; ++h) {
    if (acting_hand_[h] && has_sample_[h]) age_ns = std::max(age_ns, static_cast<double>(now_ns - last_sample_ns_[h]));
  }
  report_.glove_age_ms = age_ns * 1e-6;
}

void Station::release_forces(std::uint8_t hand) noexcept {
  for (std::size_t i = 0; i < fingers_.size(); ++i) {
    if (settings_.fingers[i].hand != hand) continue;
    fingers_[i].in_contact = false;
    fingers_[i].reaction = deform::Vec3{};
    fingers_[i].haptic_force = deform::Vec3{};
    shaper_.release(i);
    // A finger that comes back starts a new stroke: no force may be formed from a position
    // recorded before the glove went silent.
    tracks_[i].dead_band.reset();
    tracks_[i].filter.reset();
  }
}

void Station::update_fingers(std::int64_t) noexcept {
  for (std::size_t i = 0; i < fingers_.size(); ++i) {
    const FingerId id = settings_.fingers[i];
    Track& track = tracks_[i];
    track.accepted_this_tick = false;
    if (!fresh_[id.hand] || stale_[id.hand]) continue;
    const hal::GloveSample& sample = newest_[id.hand];
    const std::array<hal::Point3f, hal::kFingers> tips = settings_.hand_model.tips(sample);
    FingerState& f = fingers_[i];
    f.tracked = true;
    f.raw = {tips[id.finger][0], tips[id.finger][1], tips[id.finger][2]};
    // An inf or NaN is dropped before the filter, which would hold its last output for it (the
    // origin, before any sample) and hand that on as the finger's new position. Intake already
    // drops samples holding one; this catches finite joints whose tip overflows in the hand
    // model's arithmetic (3e38 + 3e38), and keeps the filter safe whatever feeds it.
    if (!deform::is_finite(f.raw)) {
      f.filtered = f.registered = f.raw;
      ++totals_.out_of_range;
      track.filter.reset();
      continue;
    }
    const double t = static_cast<double>(sample.device_time_us) * 1e-6;
    f.filtered = settings_.filter_enabled ? to_vec3(track.filter.filter(to_array(f.raw), t)) : f.raw;
    f.registered = to_vec3(settings_.registration.apply(to_array(f.filtered)));
    // A frame with a valid CRC may still carry 1e30: such a fingertip is dropped here, counted,
    // and the filter forgets it so it cannot drag the next good sample.
    if (!deformer_.probe_in_range(f.registered)) {
      ++totals_.out_of_range;
      track.filter.reset();
      continue;
    }
    track.accepted_this_tick = track.dead_band.offer(to_array(f.registered));
  }
  if (recorder_ && (fresh_[0] || fresh_[1])) {
    for (std::size_t i = 0; i < fingers_.size(); ++i) accepted_[i] = tracks_[i].accepted_this_tick;
    recorder_->fingertips(report_.tick, settings_.fingers, fingers_, std::span(accepted_).first(fingers_.size()));
  }
}

void Station::size_region(std::int64_t budget_ns) noexcept {
  if (settings_.region.kind != RegionPolicy::Kind::kAuto || !region_sizer_.ready()) return;
  // Every finger present may press: size for all of them, nearest points first (the region is
  // a ball around each contact).
  deformer_.set_region_radius(region_sizer_.next_radius(deformer_.settings().region.radius, last_frame_->region_points,
                                                        probes_.size(), static_cast<double>(budget_ns),
                                                        deformer_.model().size()));
}

void Station::run_frame(std::int64_t budget_ns) noexcept {
  probes_.clear();
  probe_finger_.clear();
  probe_ids_.clear();
  for (std::size_t i = 0; i < fingers_.size(); ++i) {
    const DeadBand& band = tracks_[i].dead_band;
    if (band.history_size() == 0) continue;
    deform::ProbeMotion motion;
    motion.current = to_vec3(band.current());
    motion.previous = band.history_size() >= 2 ? to_vec3(band.previous()) : motion.current;
    if (band.history_size() >= 3) motion.earlier = to_vec3(band.earlier());
    probes_.push_back(motion);
    probe_finger_.push_back(i);
    probe_ids_.push_back(settings_.fingers[i]);
  }
  if (probes_.empty()) return;
  if (static_cast<std::size_t>(frame_id_) < region_schedule_.size() &&
      region_schedule_[static_cast<std::size_t>(frame_id_)] > 0.0) {
    deformer_.set_region_radius(region_schedule_[static_cast<std::size_t>(frame_id_)]);
  } else {
    size_region(budget_ns);
  }
  const std::int64_t start = monotonic_now_ns();
  const deform::FrameReport& frame = deformer_.deform(probes_);
  report_.deform_ns = static_cast<double>(monotonic_now_ns() - start);
  last_frame_ = &frame;
  report_.frame = true;
  report_.collisions = frame.collisions;
  report_.region_points = frame.region_points;
  report_.region_radius = deformer_.settings().region.kind == deform::RegionSettings::Kind::kRadius
                              ? deformer_.settings().region.radius
                              : 0.0;
  ++totals_.frames;
  totals_.collisions += frame.collisions;
  if (frame.collisions > 0) totals_.collision_frame_time.add(std::llround(report_.deform_ns));
  totals_.max_region_points = std::max(totals_.max_region_points, frame.region_points);
  totals_.max_region_radius = std::max(totals_.max_region_radius, report_.region_radius);
  // A region that held the whole model, or more of it than a region frame pays for, ran as the
  // global frame: its cost per point is the global frame's, kept apart by the sizer.
  region_sizer_.observe(frame.region_points, frame.collisions, report_.deform_ns, frame.global);
  // Each frame the deformer applied is a frame of its own in the log (a split step holds
  // several), with consecutive ids, so replay reproduces the step exactly.
  const auto applied = deformer_.frames();
  if (recorder_) {
    for (std::size_t k = 0; k < applied.size(); ++k) {
      FrameRecord record;
      record.tick = report_.tick;
      record.time_s = static_cast<double>(now_ns_ - first_tick_ns_) * 1e-9;
      record.frame_id = frame_id_ + static_cast<std::int64_t>(k);
      record.report = &applied[k];
      record.settings = &deformer_.settings();
      record.fingers = probe_ids_;
      record.probes = probes_;
      recorder_->frame(record);
    }
  }
  frame_id_ += static_cast<std::int64_t>(std::max<std::size_t>(applied.size(), 1));
  totals_.guards += frame.guards;
  report_.guards = frame.guards;
  report_.min_jacobian = frame.min_jacobian;
  // A fresh snapshot when the index's list of moved points (which keeps its queries exact and
  // cheap however far the points drifted) is half full; without a complete list, when the
  // points have drifted. Rebuilding for drift alone while the list holds would keep the second
  // core building a large model's tree nonstop for nothing: on two million points that widened
  // the tick's tail (p99.9 0.53 -> 1.19 ms in one minute's run with 59 rebuilds against 2).
  const deform::PointIndex& index = deformer_.index();
  const bool rebuild =
      index.moved_complete() ? 2 * index.moved_count() > index.moved_capacity() : deformer_.drift() > rebuild_drift_;
  if (rebuild) {
    rebuilder_.request(deformer_.model(), deformer_.drift());
  }
  for (std::size_t k = 0; k < probes_.size(); ++k) {
    const deform::ContactReport& c = frame.contacts[k];
    FingerState& f = fingers_[probe_finger_[k]];
    f.in_contact = c.state == deform::ProbeState::kCollided;
    if (f.in_contact) ++f.collisions;
    // The surface pushes back on the finger with minus the traction it carries, summed over
    // the stroke (superposition), in newtons; into the glove frame by the registration's
    // rotation (forces do not scale with positions). A finger that let go feels nothing.
    if (!f.in_contact) {
      f.reaction = deform::Vec3{};
    } else if (c.has_traction) {
      f.reaction += to_glove_frame(-c.traction_resultant) * newtons_per_model_area_;
      if (!deform::is_finite(f.reaction)) {  // the safe state: nothing, not the last force
        f.reaction = deform::Vec3{};
        ++totals_.haptic_faults;
      }
    }
    if (c.pushed_out) {
      DeadBand& band = tracks_[probe_finger_[k]].dead_band;
      band.reset();
      band.offer(to_array(c.probe_after));
    }
  }
}

deform::Vec3 Station::to_glove_frame(const deform::Vec3& v) const noexcept {
  const Matrix3& r = settings_.registration.rotation();  // R^T v: the inverse rotation
  deform::Vec3 out;
  for (int i = 0; i < 3; ++i) out[i] = r[0][i] * v.x + r[1][i] * v.y + r[2][i] * v.z;
  return out;
}

void Station::send_haptics() noexcept {
  if (!haptic_) return;
  const auto heartbeat_ns = static_cast<std::int64_t>(settings_.haptic.heartbeat_s * 1e9);
  for (std::uint8_t hand = 0; hand < hal::kHands; ++hand) {
    if (!acting_hand_[hand]) continue;
    hal::HapticCommand command;
    command.hand = hand;
    command.tick = static_cast<std::uint32_t>(report_.tick);
    bool touching = false;
    for (std::size_t i = 0; i < fingers_.size(); ++i) {
      const FingerId id = settings_.fingers[i];
      if (id.hand != hand) continue;
      FingerState& f = fingers_[i];
      if (!f.in_contact) shaper_.release(i);
      f.haptic_force = f.in_contact ? shaper_.step(i, f.reaction) : deform::Vec3{};
      touching |= f.in_contact;
      if (f.in_contact) command.active_mask |= static_cast<std::uint8_t>(1u << id.finger);
      const deform::Vec3& v = f.haptic_force;
      command.force[id.finger] = {static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z)};
    }
    const bool released = hand_touching_[hand] && !touching;
    const bool heartbeat = now_ns_ - last_command_ns_[hand] >= heartbeat_ns;
    hand_touching_[hand] = touching;
    if (!touching && !released && !heartbeat) continue;
    const bool taken = haptic_->send(command);
    if (touching) {
      ++totals_.contact_ticks[hand];
      if (taken) ++totals_.contact_commands[hand];
    }
    last_command_ns_[hand] = now_ns_;
    if (recorder_) recorder_->haptic(command);
  }
}

const TickReport& Station::tick(std::int64_t now_ns, std::int64_t budget_ns) noexcept {
  report_ = TickReport{};
  report_.tick = totals_.ticks++;
  now_ns_ = now_ns;
  if (first_tick_ns_ < 0) first_tick_ns_ = now_ns;
  report_.budget_ns = budget_ns;
  if (rebuilder_.install(deformer_)) ++totals_.index_rebuilds;
  rebuilder_.advance(deformer_.model());
  take_samples(now_ns);
  // Each hand has its own age: a silent hand's fingers are released within one tick and cannot
  // deform until it reports again, while the other hand goes on sculpting.
  const auto timeout_ns = static_cast<std::int64_t>(std::llround(settings_.glove_timeout_s * 1e9));
  bool any = false, any_live = false, any_stale = false;
  for (std::uint8_t h = 0; h < hal::kHands; ++h) {
    if (!acting_hand_[h]) continue;
    any |= has_sample_[h];
    const bool stale = !has_sample_[h] || now_ns - last_sample_ns_[h] > timeout_ns;
    if (stale && !stale_[h] && has_sample_[h]) {
      ++totals_.stale_events;
      release_forces(h);
    }
    stale_[h] = stale;
    any_live |= !stale;
    any_stale |= stale && has_sample_[h];
  }
  report_.glove = !any ? GloveState::kWaiting : (any_stale || !any_live ? GloveState::kStale : GloveState::kLive);
  if (any_stale || !any_live) ++totals_.stale_ticks;
  if (!any_live) {
    send_haptics();
    return report_;
  }
  update_fingers(now_ns);
  report_.out_of_range = totals_.out_of_range;
  const bool moved = std::any_of(tracks_.begin(), tracks_.end(), [](const Track& t) { return t.accepted_this_tick; });
  if (moved) run_frame(budget_ns);
  send_haptics();
  return report_;
}

}  // namespace sculpt::rt
