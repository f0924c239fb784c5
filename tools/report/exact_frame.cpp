#include "exact_frame.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace sculpt::tools::report {

using deform::Vec3;

namespace {

// Points of `s` within `radius` of `q`, ascending: the brute-force twin of an index query.
void within(const ExactState& s, const Vec3& q, double radius, std::vector<std::uint32_t>& out) {
  out.clear();
  const double r2 = radius * radius;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (squared_norm(s.position[i] - q) <= r2) out.push_back(static_cast<std::uint32_t>(i));
  }
}

// The finger's size in points, as the deformer fixes it at set-up: the median eps-ball count
// over 64 evenly spread points of the undeformed model, times the guard's fraction.
std::size_t typical_patch(const ExactState& s, double radius, double fraction) {
  const std::size_t n = s.size();
  const std::size_t samples = std::min<std::size_t>(n, 64);
  std::vector<std::size_t> counts;
  std::vector<std::uint32_t> found;
  for (std::size_t k = 0; k < samples; ++k) {
    within(s, s.position[k * n / samples], radius, found);
    counts.push_back(found.size());
  }
  std::nth_element(counts.begin(), counts.begin() + static_cast<std::ptrdiff_t>(samples / 2), counts.end());
  return std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(fraction * double(counts[samples / 2]))));
}

Vec3 row(const deform::Mat3& m, int r) { return {m(r, 0), m(r, 1), m(r, 2)}; }

}  // namespace

ExactFrame::ExactFrame(const deform::PointModel& initial, const deform::DeformSettings& settings)
    : settings_(settings) {
  settings_.region = deform::RegionSettings{};
  settings_.traction = false;
  const ExactState s = ExactState::from(initial);
  min_patch_points_ = typical_patch(s, settings_.contact.bc_radius, settings_.guards.min_patch_fraction);
  // deform::side_smoothing: eps, shrunk where an eps-ball holds more than 24 points.
  const double ball = static_cast<double>(typical_patch(s, settings_.contact.bc_radius, 1.0));
  smoothing_ = settings_.contact.bc_radius * (ball > 24.0 ? std::sqrt(24.0 / ball) : 1.0);
  centre_ = initial.bounding_box_centre();
  probe_range_ = settings_.guards.probe_range * std::max(initial.bounding_box_diagonal(), 1e-30);
}

std::uint32_t ExactFrame::nearest(const ExactState& s, const Vec3& q) const {
  std::uint32_t best = deform::PointIndex::kNoPoint;
  double best_d2 = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < s.size(); ++i) {
    const double d2 = squared_norm(s.position[i] - q);
    if (d2 < best_d2) {
      best_d2 = d2;
      best = static_cast<std::uint32_t>(i);
    }
  }
  return best;
}

Vec3 ExactFrame::outside_at(const ExactState& s, std::uint32_t i) const {
  return s.has_normals() ? s.normal[i] : normalized(*settings_.contact.reference - s.position[i]);
}

// deform::locate's side (contact.hpp), over every point in double: A's plane, and the
// moving-least-squares surface of the points around q through A; across when either says so.
double ExactFrame::side(const ExactState& s, std::uint32_t a, const Vec3& q) const {
  const Vec3 pa = s.position[a];
  const double plane = dot(outside_at(s, a), q - pa);
  const double h = smoothing_;
  const double d2 = squared_norm(q - pa);
  if (!(h > 0.0) || !(std::sqrt(d2) <= 2.0 * h)) return plane;
  double weight_q = 0.0, sum_q = 0.0, weight_a = 0.0, sum_a = 0.0;
  for (std::uint32_t i = 0; i < s.size(); ++i) {
    const Vec3 p = s.position[i];
    const double tq = std::max(0.0, (squared_norm(q - p) - d2) / (4.0 * h * h));
    const double ta = squared_norm(pa - p) / (4.0 * h * h);
    if (tq < 1.0) {
      weight_q += (1.0 - tq) * (1.0 - tq);
      sum_q += (1.0 - tq) * (1.0 - tq) * dot(outside_at(s, i), q - p);
    }
    if (ta < 1.0) {
      weight_a += (1.0 - ta) * (1.0 - ta);
      sum_a += (1.0 - ta) * (1.0 - ta) * dot(outside_at(s, i), pa - p);
    }
  }
  const double surface = sum_q / weight_q - sum_a / weight_a;
  return settings_.contact.mode == deform::ContactMode::kPush ? std::min(plane, surface) : std::max(plane, surface);
}

Vec3 ExactFrame::outward(const ExactState& s, std::uint32_t a) const {
  Vec3 out = s.has_normals() ? s.normal[a] : normalized(*settings_.contact.reference - s.position[a]);
  if (squared_norm(out) == 0.0) out = Vec3{0.0, 0.0, 1.0};
  return settings_.contact.mode == deform::ContactMode::kPull ? -out : out;
}

Vec3 ExactFrame::clear_source(const ExactState& s, const Vec3& candidate, const Vec3& contact, const Vec3& force,
                              std::uint32_t a, double clearance, bool& moved) const {
  // MATH.md §4: the source keeps its clearance from every model point, and no point may sit much
  // closer to it than A (the 1/R field would move it further than A is asked to move). The
  // deformer tries the way the probe came, then A's outside, doubling the distance; the same
  // order here, so that both place the source at the same spot.
  constexpr double kAloneRatio = 0.5;
  // Its nearest point's distance over the distance it must keep (>= 1: clear); where no place
  // tried is clear, the deformer takes the most alone one, and so does this.
  auto alone = [&](const Vec3& p) {
    const double needed = std::max(clearance, kAloneRatio * norm(p - contact));
    return norm(s.position[nearest(s, p)] - p) / (needed * (1.0 - 1e-6));
  };
  moved = false;
  if (alone(candidate) >= 1.0) return candidate;
  moved = true;
  const Vec3 allowed = outward(s, a);
  Vec3 best = candidate;
  double best_alone = alone(candidate);
  const std::array<Vec3, 2> directions = {normalized(-force), allowed};
  for (const Vec3& dir : directions) {
    if (!(dot(dir, allowed) > 0.5)) continue;
    for (int k = 0; k < 4; ++k) {
      const Vec3 placed = contact + dir * (clearance * std::ldexp(1.0, k));
      const double how = alone(placed);
      if (how >= 1.0) return placed;
      if (how > best_alone) {
        best = placed;
        best_alone = how;
      }
    }
  }
  return best;
}

void ExactFrame::patch(const ExactState& s, const Vec3& centre, const Vec3& u0, bool widen,
                       std::vector<deform::DisplacementCondition>& rows, deform::GuardCounts& guards) const {
  double radius = settings_.contact.bc_radius;
  std::vector<std::uint32_t> found;
  within(s, centre, radius, found);
  if (widen && found.size() < min_patch_points_) {
    ++guards.patch_widened;
    for (int k = 0; k < 4 && found.size() < min_patch_points_; ++k) {
      radius *= std::sqrt(2.0);
      within(s, centre, radius, found);
    }
  }
  // A patch over the cap is thinned evenly in index order, as the deformer sizes its buffers.
  const std::size_t cap = settings_.contact.max_patch_points;
  const std::size_t kept = std::min(found.size(), cap);
  for (std::size_t k = 0; k < kept; ++k) {
    rows.push_back({s.position[found[found.size() > cap ? k * found.size() / cap : k]], u0, 1.0});
  }
}

ExactFrame::Outcome ExactFrame::attempt(ExactState& state, std::span<const deform::ProbeMotion> probes,
                                        Attempt& a) const {
  const deform::ContactSettings& cs = settings_.contact;
  a.contacts.assign(probes.size(), Contact{});
  std::vector<deform::SourceSetup> sources;
  std::vector<deform::DisplacementCondition> rows;
  std::vector<double> distance(probes.size(), std::numeric_limits<double>::infinity());
  std::vector<std::uint32_t> near(probes.size(), deform::PointIndex::kNoPoint);
  std::vector<bool> outside(probes.size(), false);  // not across the surface: may pin it (Δr)
  auto in_range = [&](const Vec3& p) { return is_finite(p) && norm(p - centre_) <= probe_range_; };
  for (std::size_t p = 0; p < probes.size(); ++p) {
    const deform::ProbeMotion& m = probes[p];
    if (!in_range(m.current) || !in_range(m.previous) || (m.earlier && !in_range(*m.earlier))) {
      ++a.guards.probe_dropped;
      continue;
    }
    const std::uint32_t at = nearest(state, m.current);
    near[p] = at;
    distance[p] = norm(m.current - state.position[at]);
    if (!deform::crossed(cs.mode, side(state, at, m.current))) {
      outside[p] = true;
      continue;
    }
    // A previous position less than Δd across still rests on the surface; one clearly across
    // started inside and pushes nothing.
    const double tolerance = cs.mode == deform::ContactMode::kPush ? cs.min_source_distance : -cs.min_source_distance;
    if (deform::crossed(cs.mode, side(state, nearest(state, m.previous), m.previous) + tolerance)) continue;
    Contact& c = a.contacts[p];
    c.contact = state.position[at];
    deform::ForceSetup setup = deform::set_up_force(m, c.contact, cs.min_source_distance);
    const double clearance = std::max({cs.min_source_distance, settings_.guards.clearance_ratio * norm(setup.force),
                                       settings_.guards.finger_radius_clearance ? cs.bc_radius : 0.0});
    bool moved = false;
    c.source = clear_source(state, setup.source, c.contact, setup.force, at, clearance, moved);
    if (moved) ++a.guards.source_moved;
    c.force = setup.force;
    c.pressing = true;
    sources.push_back({c.source, c.force});
    patch(state, c.contact, c.force, /*widen=*/true, rows, a.guards);
    ++a.collisions;
  }
  if (a.collisions == 0) return Outcome::kNothing;
  // Δr: a free finger close to the surface pins its patch while another one presses.
  for (std::size_t p = 0; p < probes.size(); ++p) {
    // Only a finger outside pins: one that started inside is ignored, as the deformer ignores it.
    if (!outside[p]) continue;
    if (distance[p] < cs.guard_distance) patch(state, state.position[near[p]], Vec3{}, false, rows, a.guards);
  }
  const deform::WeightSolver solver(settings_.solver);
  std::vector<Vec3> weights(sources.size()), effective(sources.size());
  const deform::SolveReport solved = solver.solve(settings_.kernel, sources, rows, {}, weights, effective);
  if (solved.damped) ++a.guards.damped;
  if (!solved.ok) return Outcome::kNothing;

  // Every point: u and grad u from the superposed sources, at the positions before the move.
  const std::size_t n = state.size();
  const bool carry = state.has_normals() && settings_.field.carry_normals;
  std::vector<Vec3> moved_to(n), turned(carry ? n : 0);
  bool finite = true;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 q = state.position[i];
    Vec3 u;
    deform::Mat3 f;
    for (int d = 0; d < 3; ++d) f(d, d) = 1.0;
    for (std::size_t k = 0; k < sources.size(); ++k) {
      u += deform::displacement(settings_.kernel, sources[k].source, effective[k], q);
      const deform::Mat3 g = deform::displacement_gradient(settings_.kernel, sources[k].source, effective[k], q);
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) f(r, c) += g(r, c);
      }
    }
    // cof(F) row by row is the cross product of the other two rows; det(F) = row 0 . cof row 0.
    const Vec3 f0 = row(f, 0), f1 = row(f, 1), f2 = row(f, 2);
    const Vec3 c0 = cross(f1, f2), c1 = cross(f2, f0), c2 = cross(f0, f1);
    const double det = dot(f0, c0);
    a.min_jacobian = std::min(a.min_jacobian, det);
    a.max_displacement = std::max(a.max_displacement, norm(u));
    moved_to[i] = q + u;
    if (carry) {
      const Vec3 nn = state.normal[i];
      turned[i] = normalized(Vec3{dot(c0, nn), dot(c1, nn), dot(c2, nn)});
      finite = finite && is_finite(turned[i]);
    }
    finite = finite && is_finite(moved_to[i]) && std::isfinite(det);
  }
  if (!finite) {
    ++a.guards.non_finite;
    return Outcome::kNonFinite;
  }
  if (!(a.min_jacobian > settings_.guards.min_jacobian)) return Outcome::kFolded;
  state.position.swap(moved_to);
  if (carry) state.normal.swap(turned);
  return Outcome::kApplied;
}

std::uint32_t ExactFrame::inside_after(const ExactState& s, std::span<const deform::ProbeMotion> probes) const {
  std::uint32_t inside = 0;
  for (const deform::ProbeMotion& m : probes) {
    if (!is_finite(m.current)) continue;
    const double depth = side(s, nearest(s, m.current), m.current);
    const double across = settings_.contact.mode == deform::ContactMode::kPush ? -depth : depth;
    if (across > settings_.contact.min_source_distance) ++inside;
  }
  return inside;
}

ExactReport ExactFrame::step(ExactState& state, std::span<const deform::ProbeMotion> probes) const {
  ExactReport r;
  probes = probes.first(std::min(probes.size(), settings_.max_probes));
  auto take = [&](const Attempt& a) {
    r.guards += a.guards;
    r.collisions += a.collisions;
    ++r.frames;
    r.max_displacement = std::max(r.max_displacement, a.max_displacement);
    r.min_jacobian = std::min(r.min_jacobian, a.min_jacobian);
  };
  Attempt whole;
  const Outcome first = attempt(state, probes, whole);
  if (first == Outcome::kApplied) take(whole);
  if (first != Outcome::kFolded) {
    if (first != Outcome::kApplied) r.guards += whole.guards;
    r.probe_inside = inside_after(state, probes);
    return r;
  }
  // The fold split: sources held, each pressing probe walked from A to A + F in parts, the part
  // halved while a substep still folds (MATH.md §6; the deformer's rule, so both apply the same
  // substeps).
  r.guards += whole.guards;
  ++r.guards.fold_splits;
  std::vector<deform::ProbeMotion> sub(probes.size());
  double done = 0.0, part = 0.5;
  int depth = 1;
  const std::size_t max_frames = (std::size_t{1} << settings_.guards.max_split_depth) + 1;
  while (done < 1.0 && r.frames < max_frames) {
    const double t = std::min(1.0, done + part);
    for (std::size_t p = 0; p < probes.size(); ++p) {
      const Contact& c = whole.contacts[p];
      sub[p].earlier.reset();
      sub[p].previous = c.pressing ? c.source : probes[p].current;
      sub[p].current = c.pressing ? c.contact + c.force * t : probes[p].current;
    }
    Attempt a;
    const Outcome o = attempt(state, sub, a);
    if (o == Outcome::kFolded && depth < settings_.guards.max_split_depth) {
      r.guards += a.guards;
      ++r.guards.fold_splits;
      part *= 0.5;
      ++depth;
      continue;
    }
    if (o == Outcome::kFolded) {
      r.guards += a.guards;
      ++r.guards.fold_rejected;
      break;
    }
    if (o == Outcome::kNonFinite) {
      r.guards += a.guards;
      break;
    }
    if (o == Outcome::kApplied) take(a);
    if (o == Outcome::kNothing) r.guards += a.guards;
    done = t;
  }
  r.probe_inside = inside_after(state, probes);
  return r;
}

}  // namespace sculpt::tools::report
