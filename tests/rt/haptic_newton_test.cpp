// The haptic force in newtons, against a computation of its own. One finger presses a flat sheet
// a known depth in one frame; from the scene's numbers alone (the press, G, nu, the
// registration) the test predicts what the glove must feel and compares it with what the
// haptic sink receives, before the clamp (max_force at its largest, no slew in the way):
//   - the effective force: the least-squares fit of Kelvin's displacement (MATH.md §1, written
//     out here) to u0 = P_f - A on the finger's patch, by the normal equations;
//   - the traction: sigma n with sigma = G (grad u + grad u^T) + lambda (div u) I from central
//     differences of that displacement, never the code's traction kernel;
//   - the resultant: the traction summed over the patch, each point carrying the grid's cell
//     area (known by construction, not estimated from the points);
//   - newtons: a model unit is 1/scale metres, so Pa x model units^2 times (1/scale)^2; the
//     surface pushes the finger with minus the resultant, turned into the glove frame by R^T.
// The stress and the area sum are themselves checked against Kelvin's closed forms (the force
// on a closed surface around the source is the force; a disc's share of it).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <vector>

#include "sculpt/deform/generators.hpp"
#include "sculpt/rt/station.hpp"
#include "station_fixtures.hpp"

namespace sculpt::rt {
namespace {

using deform::Vec3;
using test_fixtures::FakeGlove;
using test_fixtures::kMs;
using Matrix = std::array<std::array<double, 3>, 3>;

constexpr double kPi = 3.14159265358979323846;

struct Material {
  double g;   // shear modulus, Pa
  double nu;  // Poisson's ratio
};

// MATH.md §1: u_l(Q) = f_k U_kl(P, Q), U_kl = [(3 - 4 nu) delta_kl + rh_k rh_l] / (16 pi G (1 - nu) R).
Vec3 kelvin_displacement(const Material& m, const Vec3& source, const Vec3& force, const Vec3& q) {
  const Vec3 r = q - source;
  const double length = std::sqrt(deform::dot(r, r));
  const Vec3 rh = r * (1.0 / length);
  const double c = 1.0 / (16.0 * kPi * m.g * (1.0 - m.nu) * length);
  return (force * (3.0 - 4.0 * m.nu) + rh * deform::dot(rh, force)) * c;
}

// Isotropic Hooke's law on a central-difference gradient of the displacement.
Matrix stress(const Material& m, const Vec3& source, const Vec3& force, const Vec3& q) {
  const double h = 1e-5 * deform::norm(q - source);
  Matrix grad{};  // grad[l][k] = d u_l / d q_k
  for (int k = 0; k < 3; ++k) {
    Vec3 step;
    step[k] = h;
    const Vec3 up = kelvin_displacement(m, source, force, q + step);
    const Vec3 down = kelvin_displacement(m, source, force, q - step);
    for (int l = 0; l < 3; ++l) grad[l][k] = (up[l] - down[l]) / (2.0 * h);
  }
  const double lambda = 2.0 * m.g * m.nu / (1.0 - 2.0 * m.nu);
  const double div = grad[0][0] + grad[1][1] + grad[2][2];
  Matrix s{};
  for (int l = 0; l < 3; ++l) {
    for (int k = 0; k < 3; ++k) s[l][k] = m.g * (grad[l][k] + grad[k][l]) + (l == k ? lambda * div : 0.0);
  }
  return s;
}

Vec3 times(const Matrix& a, const Vec3& v) {
  Vec3 out;
  for (int i = 0; i < 3; ++i) out[i] = a[i][0] * v.x + a[i][1] * v.y + a[i][2] * v.z;
  return out;
}

Vec3 traction(const Material& m, const Vec3& source, const Vec3& force, const Vec3& q, const Vec3& normal) {
  return times(stress(m, source, force, q), normal);
}

// x with a x = b, by Cramer's rule (a 3x3 normal matrix of one source: well conditioned).
Vec3 solve3(const Matrix& a, const Vec3& b) {
  auto det = [](const Matrix& x) {
    return x[0][0] * (x[1][1] * x[2][2] - x[1][2] * x[2][1]) - x[0][1] * (x[1][0] * x[2][2] - x[1][2] * x[2][0]) +
           x[0][2] * (x[1][0] * x[2][1] - x[1][1] * x[2][0]);
  };
  const double d = det(a);
  Vec3 x;
  for (int c = 0; c < 3; ++c) {
    Matrix replaced = a;
    for (int r = 0; r < 3; ++r) replaced[r][c] = b[r];
    x[c] = det(replaced) / d;
  }
  return x;
}

// The oracle first: integrated over a sphere around the source, sigma n_out must balance the
// point force exactly (the sphere's material is in equilibrium), whatever the radius.
TEST(HapticNewtons, TheTestsStressBalancesThePointForceOnAClosedSurface) {
  const Material m{3e4, 0.3};
  const Vec3 source{0.1, -0.2, 0.3}, force{0.4, -1.0, 2.5};
  for (const double radius : {0.05, 2.0}) {
    constexpr int kTheta = 200, kPhi = 400;  // midpoint rule, periodic in phi
    Vec3 total;
    for (int i = 0; i < kTheta; ++i) {
      const double theta = kPi * (i + 0.5) / kTheta;
      for (int j = 0; j < kPhi; ++j) {
        const double phi = 2.0 * kPi * (j + 0.5) / kPhi;
        const Vec3 n{std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
        const double area = radius * radius * std::sin(theta) * (kPi / kTheta) * (2.0 * kPi / kPhi);
        total += traction(m, source, force, source + n * radius, n) * area;
      }
    }
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(total[k], -force[k], 1e-4 * deform::norm(force)) << "radius " << radius;
  }
}

// A sink that keeps only the newest command: all this test needs is the held force.
class NewestCommand final : public hal::HapticSink {
 public:
  explicit NewestCommand(hal::HapticCommand* newest) : newest_(newest) {}
  void start() override {}
  void stop() override {}
  bool send(const hal::HapticCommand& c) noexcept override {
    *newest_ = c;
    ++sent_;
    if (c.active_mask != 0 && c.hand < hal::kHands) ++sent_in_contact_[c.hand];
    return true;
  }
  std::uint64_t dropped() const noexcept override { return 0; }
  std::uint64_t delivered() const noexcept override { return sent_; }
  std::uint64_t delivered_in_contact(std::size_t hand) const noexcept override {
    return hand < hal::kHands ? sent_in_contact_[hand] : 0;
  }
  const char* name() const noexcept override { return "newest"; }

 private:
  hal::HapticCommand* newest_;
  std::uint64_t sent_ = 0;
  std::array<std::uint64_t, hal::kHands> sent_in_contact_{};
};

struct Registration {
  const char* name;
  double scale;  // model units per glove metre
  AxisAngle rotation;
  std::array<double, 3> translation;
};

// A 61 x 61 sheet of pitch 0.01 (model units) in z = 0, normals +z. The index finger rests 0.1
// above its centre point A, then in one glove sample is 0.02 below it: one frame, source at the
// resting position (0.1 is clear of every point by more than the finger's radius), u0 = (0, 0,
// -0.02) on the 137 points within eps = 0.065 of A (no lattice point lies near that circle).
TEST(HapticNewtons, TheHeldForceIsTheReactionOfTheSurfaceInNewtons) {
  constexpr std::size_t kPerSide = 61;
  constexpr double kPitch = 0.01, kRadius = 0.065, kRest = 0.1, kDepth = 0.02;
  const Material material{3e4, 0.3};  // a soft gel
  const Vec3 resting{0.0, 0.0, kRest}, pressed{0.0, 0.0, -kDepth}, contact{};
  for (const Registration& reg : {Registration{"identity, 1 model unit = 1 m", 1.0, {}, {0.0, 0.0, 0.0}},
                                  Registration{"scale 10 (1 model unit = 10 cm), turned and moved",
                                               10.0,
                                               AxisAngle{{1.0, 2.0, 3.0}, 0.7},
                                               {0.05, -0.1, 0.2}}}) {
    SCOPED_TRACE(reg.name);
    deform::PointModel sheet = deform::make_plane_patch(kPerSide, kPitch);
    const deform::PointModel flat = sheet;
    StationSettings s;
    s.fingers = {{0, 1}};
    s.filter_enabled = false;
    s.delta_s = 0.005;
    s.glove_timeout_s = 0.05;
    s.region.kind = RegionPolicy::Kind::kGlobal;
    s.deform.kernel.material.shear_modulus = material.g;
    s.deform.kernel.material.poisson_ratio = material.nu;
    s.deform.contact.bc_radius = kRadius;
    s.deform.contact.min_source_distance = 0.01;
    s.deform.contact.guard_distance = 0.05;
    s.registration = SimilarityTransform::from_scale_rotation_translation(reg.scale, reg.rotation, reg.translation);
    s.haptic.gain = 1.0;
    s.haptic.max_force = 1000.0;  // the largest clamp allowed: the reaction itself reaches the sink
    s.haptic.max_force_rate = 1e12;
    auto glove = std::make_unique<FakeGlove>();
    FakeGlove* g = glove.get();
    hal::HapticCommand newest;
    Station station(sheet, s, std::move(glove), std::make_unique<NewestCommand>(&newest));
    station.start();
    const SimilarityTransform to_glove = s.registration.inverse();
    auto in_glove = [&](const Vec3& model) {
      const auto p = to_glove.apply({model.x, model.y, model.z});
      return Vec3{p[0], p[1], p[2]};
    };
    std::int64_t now = 0;
    auto tick_with = [&](const Vec3& model_point) {
      now += kMs;
      g->feed(in_glove(model_point), now, static_cast<std::uint64_t>(now / 1000));
      station.tick(now, 10 * kMs);
    };
    tick_with(resting);
    tick_with(resting);
    ASSERT_EQ(station.totals().collisions, 0u);
    const std::uint64_t frames_before = station.totals().frames;
    tick_with(pressed);
    ASSERT_EQ(station.totals().frames, frames_before + 1) << "the press is one frame";
    ASSERT_EQ(station.totals().collisions, 1u);
    const deform::ContactReport& c = station.last_frame().contacts[0];
    ASSERT_EQ(c.state, deform::ProbeState::kCollided);
    // Where the code put the source is an input of the prediction, so check it is the one
    // the prediction assumes (within the float glove sample's rounding).
    ASSERT_LT(deform::norm(c.source - resting), 1e-6) << "the source moved: the prediction below assumes it did not";
    for (int t = 0; t < 5; ++t) tick_with(pressed);  // held: the same force every tick
    ASSERT_TRUE(newest.active_mask & 0b10);
    ASSERT_EQ(newest.tick, station.totals().ticks - 1) << "the newest command is this tick's";

    // The patch and the effective force that meets u0 on it in the least-squares sense.
    std::vector<Vec3> patch;
    for (std::size_t i = 0; i < flat.size(); ++i) {
      if (deform::norm(flat.position(i) - contact) <= kRadius) patch.push_back(flat.position(i));
    }
    ASSERT_EQ(patch.size(), 137u);
    const Vec3 u0 = pressed - contact;
    Matrix normal{};
    Vec3 rhs;
    for (const Vec3& q : patch) {
      Matrix u{};  // u[l][k]: displacement l per unit force k
      for (int k = 0; k < 3; ++k) {
        Vec3 unit;
        unit[k] = 1.0;
        const Vec3 column = kelvin_displacement(material, resting, unit, q);
        for (int l = 0; l < 3; ++l) u[l][k] = column[l];
      }
      for (int a = 0; a < 3; ++a) {
        for (int b = 0; b < 3; ++b) {
          for (int l = 0; l < 3; ++l) normal[a][b] += u[l][a] * u[l][b];
        }
        for (int l = 0; l < 3; ++l) rhs[a] += u[l][a] * u0[l];
      }
    }
    const Vec3 force = solve3(normal, rhs);  // Pa x model units^2
    EXPECT_LT(deform::norm(c.effective_force - force), 1e-6 * deform::norm(force)) << "the solved force";

    // The surface's traction summed over the patch, in newtons, pushing the finger out.
    Vec3 resultant;
    for (const Vec3& q : patch) resultant += traction(material, resting, force, q, {0.0, 0.0, 1.0}) * (kPitch * kPitch);
    const double newtons_per_model_area = 1.0 / (reg.scale * reg.scale);
    const Matrix& r = s.registration.rotation();
    Vec3 expected;  // R^T (-resultant)
    for (int i = 0; i < 3; ++i) {
      expected[i] = -(r[0][i] * resultant.x + r[1][i] * resultant.y + r[2][i] * resultant.z) * newtons_per_model_area;
    }
    const Vec3 felt{newest.force[1][0], newest.force[1][1], newest.force[1][2]};
    const double error = deform::norm(felt - expected) / deform::norm(expected);
    EXPECT_LT(error, 1e-5) << "felt (" << felt.x << ", " << felt.y << ", " << felt.z << ") N, expected (" << expected.x
                           << ", " << expected.y << ", " << expected.z << ") N";

    // The area sum means what it says: Kelvin's closed form for a disc of radius a at distance h
    // from a normal point force f carries f / (4 (1 - nu)) [(1 - 2 nu)(1 - c) + 1 - c^3] of it,
    // c = h / sqrt(a^2 + h^2) (half of f over the whole plane), here for the disc whose area
    // the patch's points cover.
    const double a = kPitch * std::sqrt(static_cast<double>(patch.size()) / kPi);
    const double cz = kRest / std::sqrt(a * a + kRest * kRest);
    const double disc_share =
        ((1.0 - 2.0 * material.nu) * (1.0 - cz) + 1.0 - cz * cz * cz) / (4.0 * (1.0 - material.nu));
    EXPECT_NEAR(resultant.z / force.z, disc_share, 0.005 * disc_share);
    std::printf(
        "[ newtons ] %s: f = %.6g Pa*unit^2 (z), patch carries %.4f of it (disc closed form %.4f); "
        "felt %.6g N, expected %.6g N, relative error %.2g\n",
        reg.name, force.z, resultant.z / force.z, disc_share, deform::norm(felt), deform::norm(expected), error);
  }
}

}  // namespace
}  // namespace sculpt::rt
