#include "sculpt/deform/deformer.hpp"

#include "sculpt/deform/model_scale.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

namespace sculpt::deform {

Deformer::Deformer(PointModel& model, const DeformSettings& settings)
    : model_(model),
      settings_(settings),
      index_((settings.kernel.validate(), settings.contact.validate(), model)),
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
  const std::size_t n = model_.size();
  report_.contacts.resize(settings_.max_probes);
  sources_.reserve(kMaxSources);
  forces_.reserve(kMaxSources);
  weights_.resize(kMaxSources);
  effective_.resize(kMaxSources);
  contact_points_.reserve(kMaxSources);
  neighbours_.reserve(n);
  contact_neighbourhood_.reserve(n);
  neighbourhood_begin_.resize(settings_.max_probes + 1);
  // Each point can be a condition once per contact or guard neighbourhood and once in the band;
  // a frame needing more than this grows the vector once and keeps it.
  conditions_.reserve(std::min<std::size_t>(2 * n, n + 4096));
  if (settings_.traction) {
    // Area per point from the mean nearest-neighbour spacing s (a square grid of pitch s has
    // s^2 per point): enough to turn traction into a resultant force for haptics.
    const double spacing = typical_spacing(model_, index_).value;
    point_area_ = spacing * spacing;
  }
}

void Deformer::rebuild_index() {
  index_.rebuild(model_);
  drift_ = 0.0;
  index_holds_base_ = false;
}

void Deformer::adopt_index(PointIndex& fresh, double drift_at_snapshot) noexcept {
  std::swap(index_, fresh);
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
  if (index_holds_base_) {
    drift_ = 0.0;
  } else {
    index_.rebuild(model_);
    drift_ = 0.0;
    index_holds_base_ = true;
  }
}

std::size_t Deformer::add_neighbourhood(const Vec3& centre, const Vec3& displacement, bool record) {
  index_.within_radius(model_, centre, settings_.contact.bc_radius, neighbours_, drift_);
  for (std::uint32_t j : neighbours_) {
    conditions_.push_back({model_.position(j), displacement, 1.0});
    if (record) contact_neighbourhood_.push_back(j);
  }
  return neighbours_.size();
}

double Deformer::field_magnitude_max(std::span<const std::uint32_t> points) const {
  double largest = 0.0;
  for (std::uint32_t j : points) {
    Vec3 u;
    for (const SourceForce& f : forces_) u += displacement(settings_.kernel, f.source, f.force, model_.position(j));
    largest = std::max(largest, norm(u));
  }
  return largest;
}

void Deformer::compute_tractions() {
  for (std::size_t p = 0; p + 1 < neighbourhood_begin_.size(); ++p) {
    ContactReport& c = report_.contacts[p];
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
      c.traction_resultant += traction_at(contact_neighbourhood_[k]) * point_area_;
    }
    c.has_traction = true;
  }
}

void Deformer::keep_probes_outside(std::span<const ProbeMotion> probes) {
  const ContactSettings& cs = settings_.contact;
  for (std::size_t p = 0; p < probes.size(); ++p) {
    ContactReport& c = report_.contacts[p];
    const SurfaceSide after = locate(model_, index_, drift_, probes[p].current, cs);
    c.side_after = after.side;
    c.probe_after = probes[p].current;
    const bool free_finger = c.state == ProbeState::kFree || c.state == ProbeState::kGuarded;
    if (!free_finger || !crossed(cs.mode, after.side)) continue;
    // Thesis 4.3.2.1: a finger that an extreme update left across the surface is moved to the
    // nearest point's allowed side, Δd off the surface, so the next frame cannot go singular.
    const Vec3 a = model_.position(after.nearest);
    Vec3 outward = model_.has_normals() ? model_.normal(after.nearest) : normalized(*cs.reference - a);
    if (cs.mode == ContactMode::kPull) outward = -outward;
    c.probe_after = a + outward * cs.min_source_distance;
    c.pushed_out = true;
    c.side_after = locate(model_, index_, drift_, c.probe_after, cs).side;
  }
}

const FrameReport& Deformer::deform(std::span<const ProbeMotion> probes) noexcept {
  const ContactSettings& cs = settings_.contact;
  const std::size_t count = std::min(probes.size(), settings_.max_probes);
  probes = probes.first(count);
  FrameReport& r = report_;
  r.collisions = 0;
  r.solve = SolveReport{};
  r.region_points = r.border_points = r.displacement_conditions = 0;
  r.max_displacement = r.max_contact_displacement = r.max_border_displacement = 0.0;
  sources_.clear();
  forces_.clear();
  conditions_.clear();
  contact_points_.clear();
  contact_neighbourhood_.clear();

  // 1. Collisions, forces and the contact boundary conditions u0 = P_f - A.
  std::size_t contact_conditions = 0;
  for (std::size_t p = 0; p < count; ++p) {
    ContactReport& c = r.contacts[p];
    c = ContactReport{};
    neighbourhood_begin_[p] = contact_neighbourhood_.size();
    const SurfaceSide now = locate(model_, index_, drift_, probes[p].current, cs);
    c.nearest = now.nearest;
    c.distance = now.distance;
    c.contact = model_.position(now.nearest);
    if (!crossed(cs.mode, now.side)) continue;
    // After a frame the probe rests on the surface up to the solve's residual, so a previous
    // position less than Δd across it still counts as on the surface; only one clearly across
    // started inside.
    const double previous_side = locate(model_, index_, drift_, probes[p].previous, cs).side;
    const double tolerance = cs.mode == ContactMode::kPush ? cs.min_source_distance : -cs.min_source_distance;
    if (crossed(cs.mode, previous_side + tolerance)) {
      c.state = ProbeState::kStartedInside;
      continue;
    }
    const ForceSetup setup = set_up_force(probes[p], c.contact, cs.min_source_distance);
    c.state = ProbeState::kCollided;
    c.source = setup.source;
    c.source_rule = setup.rule;
    c.force = setup.force;
    sources_.push_back({setup.source, setup.force});
    contact_points_.push_back(c.contact);
    c.boundary_points = add_neighbourhood(c.contact, setup.force, /*record=*/true);
    contact_conditions += c.boundary_points;
    ++r.collisions;
  }
  neighbourhood_begin_[count] = contact_neighbourhood_.size();
  if (r.collisions == 0) {
    keep_probes_outside(probes);
    return r;
  }

  // 2. Δr: a free finger near the surface pins its neighbourhood so it stays outside.
  for (std::size_t p = 0; p < count; ++p) {
    ContactReport& c = r.contacts[p];
    if (c.state != ProbeState::kFree || c.distance >= cs.guard_distance) continue;
    c.state = ProbeState::kGuarded;
    c.boundary_points = add_neighbourhood(c.contact, Vec3{}, /*record=*/false);
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
    keep_probes_outside(probes);
    return r;  // nothing finite to apply: the model stays as it was
  }

  // 5. What the frame will do at the contacts and the band, and the haptic traction, all on the
  //    undeformed configuration the solution refers to.
  r.max_contact_displacement = field_magnitude_max(contact_neighbourhood_);
  r.max_border_displacement = field_magnitude_max(band);
  if (settings_.traction) compute_tractions();

  // 6. Move the region (or everything) and carry the normals.
  r.max_displacement = apply_displacements(model_, settings_.kernel, forces_, region_.points(),
                                           region_.global(), settings_.field);
  r.region_points = region_.global() ? model_.size() : region_.points().size();
  r.border_points = band.size();
  drift_ += r.max_displacement;

  keep_probes_outside(probes);
  return r;
}

}  // namespace sculpt::deform
