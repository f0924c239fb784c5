#include "sculpt/deform/deformer.hpp"

#include "sculpt/deform/model_scale.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

namespace sculpt::deform {

namespace {

// How many points the finger's patch (an eps-ball) holds on the undeformed model, times
// `fraction`, rounded up.
std::size_t typical_patch_points(const PointModel& model, const PointIndex& index, double radius, double fraction) {
  const double median = static_cast<double>(median_ball_count(model, index, radius));
  return std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(fraction * median)));
}

}  // namespace

// A source's nearest model point is at least this fraction of its distance to A.
constexpr double kSourceAloneRatio = 0.5;

// Points the index lists as moved since its snapshot (PointIndex::track_moved): a stroke's
// regions between two rebuilds fit easily; beyond it (a global frame moves every point) queries
// widen by the drift as before.
constexpr std::size_t kMovedCapacity = std::size_t{1} << 16;
// The list is read once the drift is this many bc radii (about spacings): measured on a
// two-million-point sphere, a single five-finger frame costs the same either way there.
constexpr double kMovedListFromDrift = 8.0;

void GuardSettings::validate() const {
  auto fail = [](const std::string& what) { throw std::invalid_argument("deform guards: " + what); };
  if (!(clearance_ratio >= 0.0 && clearance_ratio <= 1e3)) fail("clearance ratio must lie in [0, 1000]");
  if (!(min_jacobian >= 0.0 && min_jacobian < 1.0)) fail("min jacobian must lie in [0, 1)");
  if (max_split_depth < 0 || max_split_depth > 10) fail("max split depth must lie in 0..10");
  if (!(min_patch_fraction >= 0.0 && min_patch_fraction <= 1.0)) fail("min patch fraction must lie in [0, 1]");
  if (!(probe_range > 0.0) || !std::isfinite(probe_range)) fail("probe range must be positive and finite");
}

GuardCounts& GuardCounts::operator+=(const GuardCounts& o) noexcept {
  source_moved += o.source_moved;
  fold_splits += o.fold_splits;
  fold_rejected += o.fold_rejected;
  non_finite += o.non_finite;
  pushed_out += o.pushed_out;
  damped += o.damped;
  probe_dropped += o.probe_dropped;
  patch_widened += o.patch_widened;
  return *this;
}

std::uint32_t GuardCounts::total() const noexcept {
  std::uint32_t sum = 0;
  for_each_guard(*this, [&](const char*, std::uint32_t v) { sum += v; });
  return sum;
}

Deformer::Deformer(PointModel& model, const DeformSettings& settings)
    : model_(model),
      settings_(settings),
      index_((settings.kernel.validate(), settings.contact.validate(), settings.guards.validate(), model)),
      region_(settings.region, model, index_, settings.contact.bc_radius),
      solver_(settings.solver) {
  if (model_.empty()) throw std::invalid_argument("deform: the model has no points");
  if (!model_.has_normals() && !settings_.contact.reference) {
    throw std::invalid_argument(
        "deform: the model has no normals; give a reference point known to be outside "
        "(the scanner's position) or compute normals first");
  }
  if (settings_.traction && !model_.has_normals()) {
    throw std::invalid_argument("deform: traction needs normals; the model has none");
  }
  if (settings_.max_probes == 0 || settings_.max_probes > kMaxSources) {
    throw std::invalid_argument("deform: max probes must be 1 to " + std::to_string(kMaxSources));
  }
  if (settings_.threads != 1 && settings_.threads != 2) {
    throw std::invalid_argument("deform: threads must be 1 or 2, got " + std::to_string(settings_.threads));
  }
  if (!(settings_.field.normal_skip_bound >= 0.0 && settings_.field.normal_skip_bound <= kMaxNormalSkipBound)) {
    throw std::invalid_argument("deform: normal skip bound must lie in [0, 0.1], got " +
                                std::to_string(settings_.field.normal_skip_bound));
  }
  if (settings_.threads == 2) worker_ = std::make_unique<FieldWorker>();
  const std::size_t n = model_.size();
  report_.contacts.resize(settings_.max_probes);
  folded_.contacts.resize(settings_.max_probes);
  substeps_.resize((std::size_t{1} << settings_.guards.max_split_depth) + 1);
  for (FrameReport& f : substeps_) f.contacts.resize(settings_.max_probes);
  sub_probes_.reserve(settings_.max_probes);
  journal_.reserve(n, model_.has_normals());
  // Below a few spacings of drift, widening a query visits fewer points than the list holds.
  index_.track_moved(kMovedCapacity, kMovedListFromDrift * settings_.contact.bc_radius);
  centre_ = model_.bounding_box_centre();
  extent_ = largest_coordinate(model_);
  probe_range_ = settings_.guards.probe_range * std::max(model_.bounding_box_diagonal(), 1e-30);
  min_patch_points_ =
      typical_patch_points(model_, index_, settings_.contact.bc_radius, settings_.guards.min_patch_fraction);
  sources_.reserve(kMaxSources);
  forces_.reserve(kMaxSources);
  weights_.resize(kMaxSources);
  effective_.resize(kMaxSources);
  contact_points_.reserve(kMaxSources);
  neighbours_.reserve(n);
  side_neighbours_.reserve(n);
  side_smoothing_ = side_smoothing(model_, index_, settings_.contact.bc_radius);
  // A located probe's balls hold a few hundred points (4h and the margin, 24 points to an
  // h-ball); two per finger and frame fit many times over.
  constexpr std::size_t kProbeBallPoints = 65536;
  probe_balls_ = BallCache(std::min(n, kProbeBallPoints), BallCache::kProbeMargin, /*ascending=*/true);
  // Every finger's patch holds at most max_patch_points (thinned beyond), so the worst frame
  // is every probe's full patch plus the region's band (at most every point).
  const std::size_t patch = std::min(n, settings_.contact.max_patch_points);
  contact_neighbourhood_.reserve(settings_.max_probes * patch);
  patch_area_scale_.assign(settings_.max_probes, 1.0);
  neighbourhood_begin_.resize(settings_.max_probes + 1);
  probe_hints_.assign(settings_.max_probes, PointIndex::kNoPoint);
  // Each point can be a condition once per contact or guard neighbourhood and once in the band;
  // a frame needing more than this grows the vector once and keeps it.
  conditions_.reserve(settings_.max_probes * patch + n);
  if (settings_.traction) {
    // Area per point from the typical nearest-neighbour spacing s (a square grid of pitch s has
    // s^2 per point): enough to turn traction into a resultant force for haptics.
    const double spacing = typical_spacing(model_, index_).value;
    point_area_ = spacing * spacing;
  }
}

void Deformer::rebuild_index() {
  index_.rebuild(model_);
  // The positions may have been written from outside (sculpt report stores its exact state in
  // the model): what was known of how far they could have moved holds no longer.
  extent_ = largest_coordinate(model_);
  region_.remeasure(model_);
  probe_balls_.forget();
  drift_ = 0.0;
  index_holds_base_ = false;
}

void Deformer::adopt_index(PointIndex& fresh, double drift_at_snapshot) noexcept {
  std::swap(index_, fresh);
  index_.take_moved(fresh, model_);
  // Points moved since the snapshot by at most the displacements applied after it.
  drift_ = std::max(0.0, drift_ - drift_at_snapshot);
  index_holds_base_ = false;
}

double Deformer::set_region_radius(double radius) noexcept {
  region_.set_radius(radius);
  settings_.region.radius = region_.settings().radius;
  return settings_.region.radius;
}

double Deformer::min_region_radius() const noexcept { return region_.min_radius(); }

void Deformer::restore(const PointModel& base) {
  if (base.size() != model_.size() || base.has_normals() != model_.has_normals()) {
    throw std::invalid_argument("deform: restore needs the base model the deformer was built on");
  }
  std::copy(base.x.begin(), base.x.end(), model_.x.begin());
  std::copy(base.y.begin(), base.y.end(), model_.y.begin());
  std::copy(base.z.begin(), base.z.end(), model_.z.begin());
  std::copy(base.nx.begin(), base.nx.end(), model_.nx.begin());
  std::copy(base.ny.begin(), base.ny.end(), model_.ny.begin());
  std::copy(base.nz.begin(), base.nz.end(), model_.nz.begin());
  extent_ = largest_coordinate(model_);
  region_.back_to_base();
  probe_balls_.forget();
  if (index_holds_base_) {
    drift_ = 0.0;
    index_.forget_moved();
  } else {
    index_.rebuild(model_);
    drift_ = 0.0;
    index_holds_base_ = true;
  }
}

std::size_t Deformer::add_neighbourhood(const Vec3& centre, const Vec3& displacement, bool record, bool widen,
                                        FrameReport& r) noexcept {
  double radius = settings_.contact.bc_radius;
  // neighbours_ holds the whole model (reserved at set-up), so every query here is complete.
  probe_balls_.within_radius(model_, index_, drift_, centre, radius, neighbours_);
  // A long push can leave A alone in its eps-ball (a needle): the finger's patch is the
  // finger's size, so the ball grows until it holds the points an eps-ball holds on the
  // undeformed model (up to 4 eps).
  if (widen && neighbours_.size() < min_patch_points_) {
    ++r.guards.patch_widened;
    for (int k = 0; k < 4 && neighbours_.size() < min_patch_points_; ++k) {
      radius *= std::sqrt(2.0);
      probe_balls_.within_radius(model_, index_, drift_, centre, radius, neighbours_);
    }
  }
  // Beyond the cap, keep every k-th point (k = size / cap, fractional): an even thinning of the
  // patch, in place and in index order.
  const std::size_t cap = settings_.contact.max_patch_points;
  last_patch_scale_ = 1.0;
  if (neighbours_.size() > cap) {
    const std::size_t found = neighbours_.size();
    for (std::size_t k = 0; k < cap; ++k) neighbours_[k] = neighbours_[k * found / cap];
    neighbours_.resize(cap);
    last_patch_scale_ = static_cast<double>(found) / static_cast<double>(cap);
    ++r.patches_thinned;
  }
  for (std::uint32_t j : neighbours_) {
    conditions_.push_back({model_.position(j), displacement, 1.0});
    if (record) contact_neighbourhood_.push_back(j);
  }
  return neighbours_.size();
}

double Deformer::field_magnitude_max(std::span<const std::uint32_t> points) const noexcept {
  // The kernel's coefficients once, not once per point and source (displacement() derives them
  // from the material each call: most of this loop's time over a region's band).
  const KernelCoefficients k = coefficients(settings_.kernel);
  double largest_squared = 0.0;
  for (std::uint32_t j : points) {
    const Vec3 q = model_.position(j);
    Vec3 u;
    for (const SourceForce& f : forces_) {
      const Mat3 m = displacement_matrix(k, f.source, q);
      for (int c = 0; c < 3; ++c) u[c] += m(c, 0) * f.force.x + m(c, 1) * f.force.y + m(c, 2) * f.force.z;
    }
    largest_squared = std::max(largest_squared, squared_norm(u));
  }
  return std::sqrt(largest_squared);
}

void Deformer::compute_tractions(FrameReport& r) noexcept {
  for (std::size_t p = 0; p + 1 < neighbourhood_begin_.size(); ++p) {
    ContactReport& c = r.contacts[p];
    if (c.state != ProbeState::kCollided) continue;
    auto traction_at = [&](std::uint32_t j) {
      Vec3 t;
      for (const SourceForce& f : forces_) {
        t += traction(settings_.kernel, f.source, f.force, model_.position(j), model_.normal(j));
      }
      return t;
    };
    c.traction = traction_at(c.nearest);
    c.traction_resultant = Vec3{};
    for (std::size_t k = neighbourhood_begin_[p]; k < neighbourhood_begin_[p + 1]; ++k) {
      c.traction_resultant += traction_at(contact_neighbourhood_[k]) * (point_area_ * patch_area_scale_[p]);
    }
    c.has_traction = true;
  }
}

SurfaceSide Deformer::locate_probe(const Vec3& probe, std::uint32_t hint) noexcept {
  return locate(model_, index_, drift_, probe, settings_.contact, side_smoothing_, side_neighbours_, hint,
                &probe_balls_);
}

Vec3 Deformer::outward(std::uint32_t point) const noexcept {
  const ContactSettings& cs = settings_.contact;
  Vec3 side = model_.has_normals() ? model_.normal(point) : normalized(*cs.reference - model_.position(point));
  if (squared_norm(side) == 0.0) side = Vec3{0.0, 0.0, 1.0};
  return cs.mode == ContactMode::kPull ? -side : side;
}

Vec3 Deformer::clear_source(const Vec3& candidate, const Vec3& contact, const Vec3& force, std::uint32_t nearest,
                            double clearance, bool& moved) noexcept {
  moved = false;
  // How alone a source at p stands: its nearest model point's distance over the distance it
  // must keep (>= 1: clear). Beyond the clearance, no model point may sit much closer to the
  // source than A does: Kelvin's field falls as 1/R, so a point at half A's distance moves twice
  // as far as A is asked to (a glove sample that jumped across the model makes such a source).
  // Float positions: a source exactly at the clearance may measure a hair closer.
  auto aloneness = [&](const Vec3& p) {
    const double needed = std::max(clearance, kSourceAloneRatio * norm(p - contact));
    return probe_balls_.nearest(model_, index_, drift_, p, nearest).distance / (needed * (1.0 - 1e-6));
  };
  if (aloneness(candidate) >= 1.0) return candidate;
  // MATH.md §4 and §6: a source next to any model point makes that point's displacement
  // unbounded, and one off the force's axis shears the patch and folds it early. First the
  // way the probe came (-F, when it leaves on the allowed side): on the force axis, which keeps
  // a straight push straight even where the carried normal has tilted; then A's normal, for a
  // tangential stroke whose -F runs along the surface. A dent may bring other points closer
  // than A, so each distance doubles until the clearance holds (four tries). Where none holds
  // (a carried normal tilted into the surface, say), the most alone of the places tried.
  moved = true;
  const Vec3 side = outward(nearest);
  const Vec3 back = normalized(-force);
  Vec3 best = candidate;
  double best_alone = aloneness(candidate);
  for (const Vec3& dir : {back, side}) {
    if (!(dot(dir, side) > 0.5)) continue;  // within 60 degrees of the allowed side
    double distance = clearance;
    for (int k = 0; k < 4; ++k, distance *= 2.0) {
      const Vec3 placed = contact + dir * distance;
      const double alone = aloneness(placed);
      if (alone >= 1.0) return placed;
      if (alone > best_alone) {
        best = placed;
        best_alone = alone;
      }
    }
  }
  return best;
}

bool Deformer::probe_in_range(const Vec3& p) const noexcept {
  return is_finite(p) && norm(p - centre_) <= probe_range_;
}

bool Deformer::probe_usable(const ProbeMotion& m) const noexcept {
  return probe_in_range(m.current) && probe_in_range(m.previous) && (!m.earlier || probe_in_range(*m.earlier));
}

void Deformer::keep_probes_outside(std::span<const ProbeMotion> probes, FrameReport& r) noexcept {
  const ContactSettings& cs = settings_.contact;
  index_.prepare_queries(model_, drift_);  // the frame's moves may have brought the list into use
  for (std::size_t p = 0; p < probes.size(); ++p) {
    ContactReport& c = r.contacts[p];
    if (c.state == ProbeState::kDropped) continue;
    const SurfaceSide after = locate_probe(probes[p].current, probe_hints_[p]);
    c.side_after = after.side;
    c.probe_after = probes[p].current;
    if (after.nearest == PointIndex::kNoPoint) continue;
    probe_hints_[p] = after.nearest;
    const double depth = cs.mode == ContactMode::kPush ? -after.side : after.side;  // > 0 across
    const bool free_finger = c.state == ProbeState::kFree || c.state == ProbeState::kGuarded;
    if (c.state == ProbeState::kCollided) c.miss = std::max(0.0, depth);
    // Thesis 4.3.2.1: a finger left across the surface is moved to the nearest point's allowed
    // side, Δd off it, so the next frame cannot start inside or go singular. A free finger may
    // not be across at all; a pressing one may rest up to Δd inside (the solve's residual).
    const double allowed = free_finger ? 0.0 : cs.min_source_distance;
    if (!(depth > allowed)) continue;
    c.probe_after = model_.position(after.nearest) + outward(after.nearest) * cs.min_source_distance;
    c.pushed_out = true;
    ++r.guards.pushed_out;
    c.side_after = locate_probe(c.probe_after, after.nearest).side;
  }
  r.max_miss = 0.0;
  for (std::size_t p = 0; p < probes.size(); ++p) r.max_miss = std::max(r.max_miss, r.contacts[p].miss);
}

Deformer::Outcome Deformer::run_frame(std::span<const ProbeMotion> probes, FrameReport& r) noexcept {
  const ContactSettings& cs = settings_.contact;
  const std::size_t count = probes.size();
  r.collisions = 0;
  r.solve = SolveReport{};
  r.region_points = r.border_points = r.displacement_conditions = 0;
  r.global = false;
  r.max_displacement = r.max_contact_displacement = r.max_border_displacement = 0.0;
  r.min_jacobian = 1.0;
  r.max_miss = 0.0;
  r.rejected = false;
  r.patches_thinned = 0;
  r.guards = GuardCounts{};
  sources_.clear();
  forces_.clear();
  conditions_.clear();
  contact_points_.clear();
  contact_neighbourhood_.clear();
  // The drift is fixed until the frame moves the model: one preparation serves its queries.
  index_.prepare_queries(model_, drift_);

  // 1. Collisions, forces and the contact boundary conditions u0 = P_f - A.
  std::size_t contact_conditions = 0;
  for (std::size_t p = 0; p < count; ++p) {
    ContactReport& c = r.contacts[p];
    c = ContactReport{};
    neighbourhood_begin_[p] = contact_neighbourhood_.size();
    const SurfaceSide now = probe_usable(probes[p]) ? locate_probe(probes[p].current, probe_hints_[p]) : SurfaceSide{};
    if (now.nearest == PointIndex::kNoPoint) {
      c.state = ProbeState::kDropped;
      ++r.guards.probe_dropped;
      continue;
    }
    probe_hints_[p] = now.nearest;
    c.nearest = now.nearest;
    c.distance = now.distance;
    c.contact = model_.position(now.nearest);
    if (!crossed(cs.mode, now.side)) continue;
    // After a frame the probe rests on the surface up to the solve's residual, so a previous
    // position less than Δd across it still counts as on the surface; only one clearly across
    // started inside.
    const double previous_side = locate_probe(probes[p].previous, now.nearest).side;
    const double tolerance = cs.mode == ContactMode::kPush ? cs.min_source_distance : -cs.min_source_distance;
    if (crossed(cs.mode, previous_side + tolerance)) {
      c.state = ProbeState::kStartedInside;
      continue;
    }
    ForceSetup setup = set_up_force(probes[p], c.contact, cs.min_source_distance);
    // A fingertip of radius eps acts on the surface like a point force at its centre, eps behind
    // the contact; a source closer than that concentrates the push on A alone (a needle).
    const double clearance = std::max({cs.min_source_distance, settings_.guards.clearance_ratio * norm(setup.force),
                                       settings_.guards.finger_radius_clearance ? cs.bc_radius : 0.0});
    bool moved = false;
    setup.source = clear_source(setup.source, c.contact, setup.force, now.nearest, clearance, moved);
    if (moved) ++r.guards.source_moved;
    c.state = ProbeState::kCollided;
    c.source = setup.source;
    c.source_rule = moved ? SourceRule::kCleared : setup.rule;
    c.force = setup.force;
    sources_.push_back({setup.source, setup.force});
    contact_points_.push_back(c.contact);
    c.boundary_points = add_neighbourhood(c.contact, setup.force, /*record=*/true, /*widen=*/true, r);
    patch_area_scale_[p] = last_patch_scale_;
    contact_conditions += c.boundary_points;
    ++r.collisions;
  }
  neighbourhood_begin_[count] = contact_neighbourhood_.size();
  if (r.collisions == 0) {
    keep_probes_outside(probes, r);
    return Outcome::kNothing;
  }

  // 2. Δr: a free finger near the surface pins its neighbourhood so it stays outside.
  for (std::size_t p = 0; p < count; ++p) {
    ContactReport& c = r.contacts[p];
    if (c.state != ProbeState::kFree || c.distance >= cs.guard_distance) continue;
    c.state = ProbeState::kGuarded;
    c.boundary_points = add_neighbourhood(c.contact, Vec3{}, /*record=*/false, /*widen=*/false, r);
  }

  // 3. The region and its pinned band; the band as a whole weighs border_weight times the
  //    contact neighbourhoods, however many points it holds.
  region_.build(model_, index_, drift_, contact_points_);
  const auto band = region_.border();
  if (!band.empty() && settings_.region.border_weight > 0.0) {
    const double w = settings_.region.border_weight *
                     std::sqrt(static_cast<double>(contact_conditions) / static_cast<double>(band.size()));
    for (std::uint32_t j : band) conditions_.push_back({model_.position(j), Vec3{}, w});
  }
  r.displacement_conditions = conditions_.size();

  // 4. Weights, then the effective forces that everything downstream uses.
  r.solve = solver_.solve(settings_.kernel, sources_, conditions_, {}, std::span(weights_).first(sources_.size()),
                          std::span(effective_).first(sources_.size()));
  if (r.solve.damped) ++r.guards.damped;
  std::size_t s = 0;
  for (std::size_t p = 0; p < count; ++p) {
    ContactReport& c = r.contacts[p];
    if (c.state != ProbeState::kCollided) continue;
    c.weights = weights_[s];
    c.effective_force = effective_[s];
    forces_.push_back({sources_[s].source, effective_[s]});
    ++s;
  }
  if (!r.solve.ok) {
    keep_probes_outside(probes, r);
    return Outcome::kNothing;  // nothing finite to apply: the model stays as it was
  }

  // 5. What the frame will do at the contacts and the band, and the haptic traction, all on the
  //    undeformed configuration the solution refers to.
  if (settings_.measure_extremes) {
    r.max_contact_displacement = field_magnitude_max(contact_neighbourhood_);
    r.max_border_displacement = field_magnitude_max(band);
  }
  if (settings_.traction) compute_tractions(r);

  // 6. Move the region (or everything) and carry the normals, keeping the old values: a frame
  //    that folds the material or yields a non-finite value is undone bit for bit.
  const FieldResult moved = apply_displacements(model_, settings_.kernel, forces_, region_.points(), region_.global(),
                                                settings_.field, /*jacobian=*/true, &journal_, worker_.get());
  // The index must hear of every position written, the undo's included (its exactness), and
  // of the drift the next queries will pass (a kept pass adds its move).
  double next_drift = drift_, next_extent = extent_;
  add_stored_move(moved.max_displacement, next_drift, next_extent);
  const auto positions_written = [&](double drift) {
    index_.note_moved(model_, region_.points_as_found(), region_.global(), drift);
  };
  positions_written(next_drift);
  r.min_jacobian = moved.min_jacobian;
  if (!moved.finite) {
    journal_.restore(model_);
    positions_written(drift_);
    r.rejected = true;
    ++r.guards.non_finite;
    keep_probes_outside(probes, r);
    return Outcome::kNonFinite;
  }
  if (!(moved.min_jacobian > settings_.guards.min_jacobian)) {
    journal_.restore(model_);
    positions_written(drift_);
    r.rejected = true;
    return Outcome::kFolded;
  }
  r.max_displacement = moved.max_displacement;
  r.normals_bounded = moved.gradients_skipped;
  r.max_normal_bound_angle = normal_bound_angle(moved.max_skipped_bound);
  r.global = region_.global();
  r.region_points = r.global ? model_.size() : region_.points().size();
  r.border_points = band.size();
  const double drift_before = drift_;
  add_stored_move(r.max_displacement, drift_, extent_);
  region_.add_move(drift_ - drift_before);
  probe_balls_.add_move(drift_ - drift_before);

  keep_probes_outside(probes, r);
  return Outcome::kApplied;
}

void Deformer::split_frame(std::span<const ProbeMotion> probes, const FrameReport& folded) noexcept {
  // The folded frame's sources, contacts and forces stay fixed; the substeps walk each probe
  // from its contact point A to its target A + F in equal parts, halving the part while a
  // substep still folds. A substep is an ordinary frame (collision detection included), so the
  // log records it as one and replay reproduces it; with its source held, each part sees a
  // smaller force against a distance that shrinks more slowly, which is what unfolds it.
  const std::size_t count = probes.size();
  std::array<bool, kMaxSources> pressing{};
  std::array<Vec3, kMaxSources> source{}, contact{}, force{};
  for (std::size_t p = 0; p < count; ++p) {
    const ContactReport& c = folded.contacts[p];
    pressing[p] = c.state == ProbeState::kCollided;
    source[p] = c.source;
    contact[p] = c.contact;
    force[p] = c.force;
  }
  carried_ = folded.guards;
  ++carried_.fold_splits;
  const int max_depth = settings_.guards.max_split_depth;
  double done = 0.0;
  double step = 0.5;
  int depth = 1;
  last_ = nullptr;
  while (done < 1.0 && applied_ < substeps_.size()) {
    const double t = std::min(1.0, done + step);
    sub_probes_.clear();
    for (std::size_t p = 0; p < count; ++p) {
      ProbeMotion m;
      if (pressing[p]) {
        m.previous = source[p];
        m.current = contact[p] + force[p] * t;
      } else {
        m.previous = m.current = probes[p].current;
      }
      sub_probes_.push_back(m);
    }
    FrameReport& r = substeps_[applied_];
    const Outcome o = run_frame(sub_probes_, r);
    last_ = &r;
    if (o == Outcome::kFolded && depth < max_depth) {
      carried_ += r.guards;
      ++carried_.fold_splits;
      step *= 0.5;
      ++depth;
      continue;
    }
    if (o == Outcome::kFolded) {
      ++r.guards.fold_rejected;
      keep_probes_outside(sub_probes_, r);
      break;
    }
    if (o == Outcome::kNonFinite) break;
    if (o == Outcome::kApplied) {
      // The attempts undone before it belong to this frame's record.
      r.guards += carried_;
      carried_ = GuardCounts{};
      ++applied_;
    }
    done = t;
  }
}

void Deformer::merge_step(std::size_t count) noexcept {
  // The step as one report: the last attempt's contacts and solve, sums and extremes over the
  // applied frames, and every guard that acted on the way.
  FrameReport& m = report_;
  const FrameReport& last = *last_;
  const bool last_applied = applied_ > 0 && last_ == &substeps_[applied_ - 1];
  for (std::size_t p = 0; p < count; ++p) m.contacts[p] = last.contacts[p];
  m.solve = last.solve;
  m.displacement_conditions = last.displacement_conditions;
  m.patches_thinned = last.patches_thinned;
  m.max_miss = last.max_miss;
  m.guards = carried_;
  if (!last_applied) m.guards += last.guards;
  m.collisions = m.region_points = m.border_points = m.normals_bounded = 0;
  m.global = false;
  m.max_displacement = m.max_contact_displacement = m.max_border_displacement = m.max_normal_bound_angle = 0.0;
  m.min_jacobian = applied_ > 0 ? 1.0 : last.min_jacobian;
  m.rejected = applied_ == 0 && last.rejected;
  for (std::size_t p = 0; p < count && applied_ > 1; ++p) m.contacts[p].traction_resultant = Vec3{};
  for (const FrameReport& f : frames()) {
    m.guards += f.guards;
    m.collisions += f.collisions;
    m.region_points += f.region_points;
    m.border_points += f.border_points;
    m.global = m.global || f.global;
    m.normals_bounded += f.normals_bounded;
    m.max_normal_bound_angle = std::max(m.max_normal_bound_angle, f.max_normal_bound_angle);
    m.max_displacement = std::max(m.max_displacement, f.max_displacement);
    m.max_contact_displacement = std::max(m.max_contact_displacement, f.max_contact_displacement);
    m.max_border_displacement = std::max(m.max_border_displacement, f.max_border_displacement);
    m.min_jacobian = std::min(m.min_jacobian, f.min_jacobian);
    if (applied_ < 2) continue;
    // By superposition the step's reaction is the sum of its frames'.
    for (std::size_t p = 0; p < count; ++p) {
      const ContactReport& c = f.contacts[p];
      if (c.state != ProbeState::kCollided) continue;
      m.contacts[p].state = ProbeState::kCollided;
      if (!c.has_traction) continue;
      m.contacts[p].has_traction = true;
      m.contacts[p].traction_resultant += c.traction_resultant;
      m.contacts[p].traction = c.traction;
    }
  }
}

const FrameReport& Deformer::deform(std::span<const ProbeMotion> probes) noexcept {
  probes = probes.first(std::min(probes.size(), settings_.max_probes));
  applied_ = 0;
  carried_ = GuardCounts{};
  FrameReport& whole = substeps_[0];
  last_ = &whole;
  const Outcome o = run_frame(probes, whole);
  if (o == Outcome::kApplied) applied_ = 1;
  if (o == Outcome::kFolded) {
    // substeps_[0] is about to be reused: keep what the folded attempt decided.
    folded_.contacts.assign(whole.contacts.begin(), whole.contacts.end());
    folded_.guards = whole.guards;
    split_frame(probes, folded_);
  }
  merge_step(probes.size());
  probe_balls_.end_frame();
  return report_;
}

}  // namespace sculpt::deform
