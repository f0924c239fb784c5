// The exact frame of sculpt report against facts that do not come from it: the Kelvin field of
// MATH.md §1 written out here, the patch reaching the probe, Nanson's normal from a numerical
// gradient of that field, and deform's own double-precision path.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "exact_frame.hpp"
#include "sculpt/deform/generators.hpp"

namespace sculpt::tools::report {
namespace {

using deform::Vec3;

constexpr double kShear = 3e7, kNu = 0.45;

// MATH.md §1, the test's own: u(Q) = 1 / (16 pi G (1 - nu) R) [(3 - 4 nu) f + (rh . f) rh].
Vec3 kelvin(const Vec3& source, const Vec3& f, const Vec3& q) {
  const Vec3 r = q - source;
  const double len = norm(r);
  const Vec3 rh = r * (1.0 / len);
  const double c = 1.0 / (16.0 * std::numbers::pi * kShear * (1.0 - kNu) * len);
  return (f * (3.0 - 4.0 * kNu) + rh * dot(rh, f)) * c;
}

deform::DeformSettings settings_for(double spacing) {
  deform::DeformSettings s;
  s.kernel.material = {kShear, kNu};
  s.contact.bc_radius = 1.2 * spacing;  // off the grid's exact neighbour distance: no ties at eps
  s.contact.min_source_distance = 0.25 * spacing;
  s.contact.guard_distance = 1.5 * spacing;
  s.solver.form = deform::WeightForm::kForce;
  return s;
}

struct Press {
  deform::PointModel model = deform::make_plane_patch(41, 0.05);  // 2 x 2 sheet in z = 0, normals +z
  deform::DeformSettings settings = settings_for(0.05);
  // A finger at the sheet's middle pressing 0.01 down from 0.1 above: no guard needs to act
  // (the clearance of 2 |F| = 0.02 and the finger's 0.05 hold at the previous position).
  std::vector<deform::ProbeMotion> probes = {{Vec3{1e-3, 2e-3, 0.1}, Vec3{1e-3, 2e-3, -0.01}, std::nullopt}};
  Vec3 centre() const { return model.bounding_box_centre(); }
  Press() {
    for (auto& p : probes) p.previous += centre(), p.current += centre();
  }
};

TEST(ReportExactFrame, EveryPointMovesByOneKelvinSource) {
  Press press;
  ExactState before = ExactState::from(press.model);
  ExactState after = before;
  const ExactFrame frame(press.model, press.settings);
  const ExactReport r = frame.step(after, press.probes);
  ASSERT_EQ(r.collisions, 1u);
  ASSERT_EQ(r.guards.total(), 0u) << "the press was meant to need no guard";
  // The source is the previous probe position (the Δd rule); its force f is what the solve
  // found. Recover f from three points' displacements (u is linear in f), then every point
  // must move by the field of that one source.
  const Vec3 source = press.probes[0].previous;
  auto probe_field = [&](std::size_t i) {
    Vec3 m[3];
    const Vec3 basis[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int k = 0; k < 3; ++k) m[k] = kelvin(source, basis[k], before.position[i]);
    return std::array<Vec3, 3>{m[0], m[1], m[2]};
  };
  // U is symmetric, so f = U^-1 u at the point nearest the contact (Cramer's rule).
  const std::size_t a = 20 * 41 + 20;
  const auto cols = probe_field(a);
  const Vec3 u = after.position[a] - before.position[a];
  const double det = dot(cols[0], cross(cols[1], cols[2]));
  const Vec3 f{dot(u, cross(cols[1], cols[2])) / det, dot(cols[0], cross(u, cols[2])) / det,
               dot(cols[0], cross(cols[1], u)) / det};
  double worst = 0.0, largest = 0.0;
  for (std::size_t i = 0; i < before.size(); ++i) {
    const Vec3 expected = kelvin(source, f, before.position[i]);
    worst = std::max(worst, norm(after.position[i] - before.position[i] - expected));
    largest = std::max(largest, norm(expected));
  }
  EXPECT_LT(worst, 1e-12 * largest);
  // That force is the least-squares one of MATH.md §3 (chapter 3 form), solved here through
  // the normal equations: the patch (points within eps of A) asked to move by F = P_f - A.
  const Vec3 big_f = press.probes[0].current - before.position[a];
  double m[3][3] = {}, b[3] = {};
  for (std::size_t i = 0; i < before.size(); ++i) {
    if (norm(before.position[i] - before.position[a]) > press.settings.contact.bc_radius) continue;
    const auto u_of = probe_field(i);  // column k: the displacement per unit force along k
    for (int r = 0; r < 3; ++r) {
      b[r] += dot(u_of[r], big_f);
      for (int c = 0; c < 3; ++c) m[r][c] += dot(u_of[r], u_of[c]);
    }
  }
  const Vec3 m0{m[0][0], m[0][1], m[0][2]}, m1{m[1][0], m[1][1], m[1][2]}, m2{m[2][0], m[2][1], m[2][2]};
  const Vec3 rhs{b[0], b[1], b[2]};
  const double dm = dot(m0, cross(m1, m2));
  // m is symmetric, so Cramer's rule on its rows solves it.
  const Vec3 solved{dot(rhs, cross(m1, m2)) / dm, dot(m0, cross(rhs, m2)) / dm, dot(m0, cross(m1, rhs)) / dm};
  EXPECT_LT(norm(solved - f), 1e-6 * norm(f));
  EXPECT_NEAR(r.max_displacement, largest, 1e-12 * largest);
}

TEST(ReportExactFrame, NormalsFollowNansonWithANumericalGradient) {
  Press press;
  ExactState before = ExactState::from(press.model);
  ExactState after = before;
  const ExactFrame frame(press.model, press.settings);
  frame.step(after, press.probes);
  // The displacement field of the frame, as the positions show it: u = after - before, sampled
  // by re-running the same frame on a model moved by h along each axis would change the solve;
  // instead the field is recovered as one Kelvin source (previous test) and differentiated here.
  const Vec3 source = press.probes[0].previous;
  const std::size_t a = 20 * 41 + 20;
  std::array<Vec3, 3> cols;
  const Vec3 basis[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (int k = 0; k < 3; ++k) cols[k] = kelvin(source, basis[k], before.position[a]);
  const Vec3 u = after.position[a] - before.position[a];
  const double det = dot(cols[0], cross(cols[1], cols[2]));
  const Vec3 f{dot(u, cross(cols[1], cols[2])) / det, dot(cols[0], cross(u, cols[2])) / det,
               dot(cols[0], cross(cols[1], u)) / det};
  for (std::size_t i : {a + 2, a + 41 * 3 + 1, a - 5 * 41 - 4}) {
    const Vec3 q = before.position[i];
    const double h = 1e-5;
    double g[3][3];  // g[l][m] = d u_l / d q_m by central differences
    for (int m = 0; m < 3; ++m) {
      Vec3 dq;
      (m == 0 ? dq.x : m == 1 ? dq.y : dq.z) = h;
      const Vec3 d = (kelvin(source, f, q + dq) - kelvin(source, f, q - dq)) * (0.5 / h);
      g[0][m] = d.x, g[1][m] = d.y, g[2][m] = d.z;
    }
    // n' ~ F^-T n with F = I + g and n = +z: the third column of F^-1, i.e. (cof F) e_z.
    const Vec3 r0{1 + g[0][0], g[0][1], g[0][2]}, r1{g[1][0], 1 + g[1][1], g[1][2]}, r2{g[2][0], g[2][1], 1 + g[2][2]};
    const Vec3 expected = normalized(Vec3{cross(r1, r2).z, cross(r2, r0).z, cross(r0, r1).z});
    EXPECT_LT(norm(after.normal[i] - expected), 1e-7) << "point " << i;
    EXPECT_GT(norm(after.normal[i] - before.normal[i]), 1e-4) << "the normal was meant to turn at point " << i;
  }
}

// The deformer's double path on the same frame: its decisions (source, patch, pinned fingers)
// are the exact frame's, so the two differ by the one rounding of the stored float result.
void expect_same_as_deformer(const Press& press) {
  deform::PointModel model = press.model;
  deform::DeformSettings d = press.settings;
  d.field.precision = deform::Precision::kDouble;
  deform::Deformer deformer(model, d);
  const deform::FrameReport& f = deformer.deform(press.probes);
  ASSERT_GE(f.collisions, 1u);
  ExactState exact = ExactState::from(press.model);
  ExactFrame(press.model, press.settings).step(exact, press.probes);
  double worst = 0.0;
  for (std::size_t i = 0; i < exact.size(); ++i) worst = std::max(worst, norm(model.position(i) - exact.position[i]));
  // The deformer rounds each coordinate (up to 1.5 here) to float once: 2^-24 x 1.5 per axis.
  EXPECT_LT(worst, 2.0 * 1.5 * std::ldexp(1.0, -24));
}

TEST(ReportExactFrame, AgreesWithTheDeformersDoublePathToFloatRounding) { expect_same_as_deformer(Press{}); }

TEST(ReportExactFrame, AgreesWithTheDeformerWhenAFreeFingerPinsItsPatch) {
  Press press;
  // A second finger 0.05 above the sheet (within Δr = 0.075), not moving: it pins its patch.
  press.probes.push_back({Vec3{0.4, 0.4, 0.05}, Vec3{0.4, 0.4, 0.05}, std::nullopt});
  expect_same_as_deformer(press);
}

TEST(ReportExactFrame, AgreesWithTheDeformerWhenAFingerStartedInside) {
  Press press;
  // A second finger already 0.05 under the sheet and going deeper: ignored, not pinned.
  press.probes.push_back({Vec3{0.4, 0.4, -0.05}, Vec3{0.4, 0.4, -0.06}, std::nullopt});
  expect_same_as_deformer(press);
}

}  // namespace
}  // namespace sculpt::tools::report
