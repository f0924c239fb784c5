#include "stroke_runner.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "sculpt/deform/model_scale.hpp"

namespace sculpt::tools::check {

using deform::Vec3;

double model_spacing(const deform::PointModel& model) {
  return deform::typical_spacing(model, deform::PointIndex(model)).value;
}

deform::DeformSettings StrokeRunner::settings_for(const deform::PointModel& model, const CaseSettings& s) {
  // The defaults `sculpt deform` derives from the spacing, so the sweep checks what users run.
  const double spacing = model_spacing(model);
  deform::DeformSettings d;
  d.kernel.kind = s.kernel;
  d.kernel.material.poisson_ratio = s.poisson_ratio;
  d.kernel.material.shear_modulus = s.shear_modulus;
  if (s.kernel == deform::KernelKind::kRegularized) d.kernel.regularization = spacing;
  d.contact.mode = deform::ContactMode::kPush;
  d.contact.bc_radius = s.bc_factor * spacing;
  d.contact.min_source_distance = 0.25 * spacing;
  d.contact.guard_distance = 1.5 * spacing;
  d.solver.form = s.form;
  d.field.precision = s.precision;
  return d;
}

namespace {
Outside into_frame(const Outside& o, const Similarity& t) {
  Outside out = o;
  out.direction = t.rotate(o.direction);
  return out;
}
}  // namespace

StrokeRunner::StrokeRunner(const deform::PointModel& base, const Outside& outside, const CaseSettings& settings,
                           const Similarity& frame, const std::vector<std::uint32_t>* mesh)
    : frame_(frame),
      outside_(into_frame(outside, frame)),
      model_(transformed(base, frame)),
      deformer_(model_, settings_for(model_, settings)),
      trace_(std::getenv("SCULPT_CHECK_TRACE") != nullptr) {
  reference_ = model_;
  outside_.reference = &reference_;
  spacing_ = deformer_.settings().contact.bc_radius / settings.bc_factor / frame_.scale;
  delta_d_ = deformer_.settings().contact.min_source_distance / frame_.scale;
  if (mesh) mesh_oracle_.emplace(*mesh, model_.size());
  metrics_.judged_by_mesh = mesh_oracle_.has_value() && mesh_oracle_->closed();
}

MeshSide StrokeRunner::mesh_surface(const Vec3& q) {
  MeshSide s = mesh_oracle_->side(model_, frame_.apply(q));
  s.distance /= frame_.scale;
  s.side /= frame_.scale;
  s.closest = frame_.unapply(s.closest);
  s.outward_normal = frame_.unrotate(s.outward_normal);
  return s;
}

PlaneSide StrokeRunner::surface(const Vec3& q) {
  PlaneSide s = oracle_.side(model_, frame_.apply(q), outside_);
  s.side /= frame_.scale;
  s.normal = frame_.unrotate(s.normal);
  s.centre = frame_.unapply(s.centre);
  return s;
}

void StrokeRunner::place(std::span<const Vec3> positions) {
  fingers_.clear();
  for (const Vec3& p : positions) fingers_.push_back({p, std::nullopt, std::nullopt});
}

bool StrokeRunner::model_finite() const {
  auto finite = [](const std::vector<float>& a) {
    return std::all_of(a.begin(), a.end(), [](float v) { return std::isfinite(v); });
  };
  return finite(model_.x) && finite(model_.y) && finite(model_.z) && finite(model_.nx) && finite(model_.ny) &&
         finite(model_.nz);
}

void StrokeRunner::press(std::span<const Vec3> targets) {
  const std::size_t n = std::min(targets.size(), fingers_.size());
  motions_.clear();
  side_before_.assign(n, 0.0);
  previous_side_.assign(n, 0.0);
  mesh_before_.assign(n, 0.0);
  mesh_previous_.assign(n, 0.0);
  for (std::size_t f = 0; f < n; ++f) {
    const Finger& g = fingers_[f];
    deform::ProbeMotion m;
    m.previous = frame_.apply(g.accepted);
    m.current = frame_.apply(targets[f]);
    if (g.earlier) m.earlier = frame_.apply(*g.earlier);
    motions_.push_back(m);
    // Judged on the model before the frame, as the deformer sees it.
    side_before_[f] = surface(targets[f]).side;
    previous_side_[f] = surface(g.accepted).side;
    if (has_mesh()) {
      mesh_before_[f] = mesh_surface(targets[f]).side;
      mesh_previous_[f] = g.mesh_side ? *g.mesh_side : mesh_surface(g.accepted).side;
    }
  }

  const deform::FrameReport& report = deformer_.deform(motions_);
  Metrics& m = metrics_;
  ++m.steps;
  m.collisions += report.collisions;
  m.guards += report.guards;
  if (!model_finite()) ++m.non_finite;
  if (report.collisions > 0 || report.rejected) m.min_jacobian = std::min(m.min_jacobian, report.min_jacobian);
  m.max_miss = std::max(m.max_miss, report.max_miss / frame_.scale);
  for (const deform::FrameReport& f : deformer_.frames()) {
    ++m.frames_applied;
    if (f.collisions == 0) continue;
    const double condition = std::isfinite(f.solve.condition) ? f.solve.condition : f.solve.effective_condition;
    m.max_condition = std::max(m.max_condition, condition);
    m.max_relative_residual = std::max(m.max_relative_residual, f.solve.relative_residual);
    double largest_force = 0.0;
    for (const deform::ContactReport& c : f.contacts) {
      if (c.state == deform::ProbeState::kCollided) largest_force = std::max(largest_force, norm(c.force));
    }
    if (largest_force > 0.0) {
      m.max_displacement_ratio = std::max(m.max_displacement_ratio, f.max_displacement / largest_force);
      if (trace_ && f.max_displacement > 3.0 * largest_force) {
        const deform::ContactReport& c = f.contacts[0];
        std::fprintf(stderr,
                     "RATIO step %zu: |F| %.4g moved %.4g, bc points %zu, source %.4g from A, rule %d, residual %.3g, "
                     "guards %u\n",
                     m.steps, largest_force, f.max_displacement, c.boundary_points, norm(c.source - c.contact),
                     static_cast<int>(c.source_rule), f.solve.relative_residual, f.guards.total());
      }
    }
  }

  // A finger that pressed in from outside past Δd must have collided; one already inside
  // before would have been counted by probe_inside at the end of last frame.
  auto judge = [&](double before, double previous, double after, bool collided, std::uint32_t& inside,
                   std::uint32_t& through, double& deepest) {
    if (before < -delta_d_ && previous >= -delta_d_ && !collided) ++through;
    if (!std::isfinite(after) || after < -delta_d_) ++inside;
    if (std::isfinite(after)) deepest = std::max(deepest, -after);
  };
  for (std::size_t f = 0; f < n; ++f) {
    const deform::ContactReport& c = report.contacts[f];
    const bool collided = c.state == deform::ProbeState::kCollided;
    // A dropped probe has no probe_after: the finger is simply where it went.
    const Vec3 after = c.state == deform::ProbeState::kDropped ? targets[f] : frame_.unapply(c.probe_after);
    const PlaneSide plane = surface(after);
    const double side = plane.side;
    judge(side_before_[f], previous_side_[f], side, collided, m.pca_probe_inside, m.pca_passed_through, m.pca_deepest);
    std::optional<MeshSide> mesh;
    if (has_mesh()) {
      mesh = mesh_surface(after);
      judge(mesh_before_[f], mesh_previous_[f], mesh->side, collided, m.mesh_probe_inside, m.mesh_passed_through,
            m.mesh_deepest);
    }
    // The counts that must be zero: a closed mesh's winding number where there is one, else the
    // PCA plane (an open sheet's mesh verdict stays beside it; see Metrics).
    if (m.judged_by_mesh) {
      judge(mesh_before_[f], mesh_previous_[f], mesh->side, collided, m.probe_inside, m.passed_through, m.deepest);
    } else {
      judge(side_before_[f], previous_side_[f], side, collided, m.probe_inside, m.passed_through, m.deepest);
    }
    if (trace_) {
      std::fprintf(stderr,
                   "step %zu finger %zu state %d before %.4g prev %.4g after %.4g code_side %.4g miss %.4g pushed %d F "
                   "%.4g rej %d nf %zu\n",
                   m.steps, f, static_cast<int>(c.state), side_before_[f], previous_side_[f], side,
                   c.side_after / frame_.scale, c.miss, c.pushed_out, norm(c.force), report.rejected,
                   deformer_.frames().size());
      const Vec3 cn = frame_.unrotate(model_.normal(plane.nearest));
      const Vec3 pa = point(plane.nearest);
      std::fprintf(stderr, "   nearest %u at (%.4g %.4g %.4g) code n (%.3g %.3g %.3g) oracle n (%.3g %.3g %.3g)\n",
                   plane.nearest, pa.x, pa.y, pa.z, cn.x, cn.y, cn.z, plane.normal.x, plane.normal.y, plane.normal.z);
      if (mesh) {
        std::fprintf(stderr,
                     "   mesh before %.4g prev %.4g after %.4g winding %.4g triangle %u closest (%.4g %.4g %.4g) "
                     "n (%.3g %.3g %.3g)\n",
                     mesh_before_[f], mesh_previous_[f], mesh->side, mesh->winding, mesh->triangle, mesh->closest.x,
                     mesh->closest.y, mesh->closest.z, mesh->outward_normal.x, mesh->outward_normal.y,
                     mesh->outward_normal.z);
        const std::uint32_t* corner = &mesh_oracle_->triangles()[3 * std::size_t{mesh->triangle}];
        for (int k = 0; k < 3; ++k) {
          const Vec3 p = point(corner[k]);
          std::fprintf(stderr, "     corner %u at (%.4g %.4g %.4g)\n", corner[k], p.x, p.y, p.z);
        }
      }
    }
    fingers_[f].earlier = fingers_[f].accepted;
    fingers_[f].accepted = after;
    fingers_[f].mesh_side = mesh ? std::optional<double>(mesh->side) : std::nullopt;
  }
}

}  // namespace sculpt::tools::check
