#include "sculpt/deform/point_index.hpp"
#include "sculpt/deform/generators.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <stdexcept>
#include <thread>
#include <vector>

namespace sculpt::deform {
namespace {

// within_radius fills its output up to the capacity and never grows it; every cloud here is
// smaller than this.
constexpr std::size_t kOutCapacity = 1 << 16;

// --- brute-force oracle: the definition of the answer, on the model's current positions ---

double squared_distance(const PointModel& m, std::size_t i, const Vec3& q) {
  const double dx = static_cast<double>(m.x[i]) - q.x;
  const double dy = static_cast<double>(m.y[i]) - q.y;
  const double dz = static_cast<double>(m.z[i]) - q.z;
  return dx * dx + dy * dy + dz * dz;
}

double oracle_nearest_distance(const PointModel& m, const Vec3& q) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < m.size(); ++i) best = std::min(best, squared_distance(m, i, q));
  return std::sqrt(best);
}

std::vector<std::uint32_t> oracle_within(const PointModel& m, const Vec3& q, double radius) {
  std::vector<std::uint32_t> out;
  out.reserve(kOutCapacity);  // within_radius never grows it
  for (std::size_t i = 0; i < m.size(); ++i) {
    if (squared_distance(m, i, q) <= radius * radius) out.push_back(static_cast<std::uint32_t>(i));
  }
  return out;
}

PointModel random_cloud(std::size_t n, std::uint32_t seed, double half_extent = 1.0) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-half_extent, half_extent);
  PointModel m;
  for (std::size_t i = 0; i < n; ++i) m.push_back({u(rng), u(rng), u(rng)});
  return m;
}

std::vector<Vec3> random_queries(std::size_t n, std::uint32_t seed, double half_extent) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-half_extent, half_extent);
  std::vector<Vec3> qs(n);
  for (Vec3& q : qs) q = {u(rng), u(rng), u(rng)};
  return qs;
}

// Moves every point by a random displacement of length at most `drift` (a fifth of them by
// exactly `drift`), and returns the largest displacement actually stored (float rounding may
// add an ulp), which is the honest bound to pass to the queries.
double displace(PointModel& m, double drift, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double moved = 0.0;
  for (std::size_t i = 0; i < m.size(); ++i) {
    const Vec3 before = m.position(i);
    const Vec3 direction = normalized(Vec3{gauss(rng), gauss(rng), gauss(rng)});
    const double length = u(rng) < 0.2 ? drift : drift * u(rng);
    m.set_position(i, before + length * direction);
    moved = std::max(moved, norm(m.position(i) - before));
  }
  return moved;
}

void expect_nearest_matches_oracle(const PointIndex& index, const PointModel& m, const Vec3& q, double drift) {
  const PointIndex::Nearest got = index.nearest(m, q, drift);
  const double want = oracle_nearest_distance(m, q);
  ASSERT_LT(got.index, m.size());
  // The point reported must really be at the reported distance, and that distance must be the
  // minimum (up to the last bits, in case the compiler fused the oracle's arithmetic).
  EXPECT_NEAR(got.distance, std::sqrt(squared_distance(m, got.index, q)), 1e-12);
  EXPECT_NEAR(got.distance, want, 1e-12 * (1.0 + want));
}

TEST(PointIndex, EmptyModelAnswersNothing) {
  const PointModel empty;
  for (const PointIndex& index : {PointIndex(), PointIndex(empty)}) {
    EXPECT_EQ(index.size(), 0u);
    const PointIndex::Nearest n = index.nearest(empty, {1, 2, 3});
    EXPECT_EQ(n.index, PointIndex::kNoPoint);
    EXPECT_TRUE(std::isinf(n.distance));
    std::vector<std::uint32_t> out{7, 8};
    index.within_radius(empty, {0, 0, 0}, 10.0, out);
    EXPECT_TRUE(out.empty());
    std::vector<std::uint32_t> ids{1};
    std::vector<double> d2{1.0};
    index.k_nearest({0, 0, 0}, 5, ids, d2);
    EXPECT_TRUE(ids.empty());
    EXPECT_TRUE(d2.empty());
  }
}

TEST(PointIndex, SinglePoint) {
  PointModel m;
  m.push_back({1, 2, 3});
  const PointIndex index(m);
  EXPECT_EQ(index.size(), 1u);
  const PointIndex::Nearest n = index.nearest(m, {1, 2, 5});
  EXPECT_EQ(n.index, 0u);
  EXPECT_DOUBLE_EQ(n.distance, 2.0);
}

TEST(PointIndex, NearestMatchesBruteForce) {
  const PointModel m = random_cloud(5000, 1234);
  const PointIndex index(m);
  ASSERT_EQ(index.size(), m.size());
  // Queries inside and well outside the cloud.
  for (const Vec3& q : random_queries(400, 99, 2.0)) expect_nearest_matches_oracle(index, m, q, 0.0);
  // Queries exactly at points find that point at distance zero.
  for (std::uint32_t i = 0; i < 5000; i += 97) {
    const PointIndex::Nearest n = index.nearest(m, m.position(i));
    EXPECT_EQ(n.index, i);
    EXPECT_EQ(n.distance, 0.0);
  }
}

TEST(PointIndex, WithinRadiusMatchesBruteForce) {
  const PointModel m = random_cloud(4000, 42);
  const PointIndex index(m);
  std::vector<std::uint32_t> out;
  out.reserve(kOutCapacity);  // within_radius never grows it
  for (const double radius : {0.0, 0.01, 0.07, 0.25, 1.0, 5.0}) {
    for (const Vec3& q : random_queries(100, 7, 1.5)) {
      index.within_radius(m, q, radius, out);
      EXPECT_EQ(out, oracle_within(m, q, radius)) << "radius " << radius;
    }
  }
  index.within_radius(m, {0, 0, 0}, 5.0, out);
  EXPECT_EQ(out.size(), m.size());  // the whole cloud, in index order
  EXPECT_TRUE(std::is_sorted(out.begin(), out.end()));
}

TEST(PointIndex, RadiusIsInclusive) {
  // Integer grid: every distance below is exact, so "within 1" must include the 6 axis
  // neighbours at exactly 1 and exclude the diagonal ones.
  PointModel m;
  for (int k = -2; k <= 2; ++k) {
    for (int j = -2; j <= 2; ++j) {
      for (int i = -2; i <= 2; ++i) m.push_back({double(i), double(j), double(k)});
    }
  }
  const PointIndex index(m);
  std::vector<std::uint32_t> out;
  out.reserve(kOutCapacity);  // within_radius never grows it
  index.within_radius(m, {0, 0, 0}, 1.0, out);
  EXPECT_EQ(out.size(), 7u);
  EXPECT_EQ(out, oracle_within(m, {0, 0, 0}, 1.0));
  index.within_radius(m, {2, 2, 2}, 0.0, out);  // radius 0 at a point: just that point
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(m.position(out[0]), (Vec3{2, 2, 2}));
  index.within_radius(m, {0.5, 0, 0}, 0.0, out);  // radius 0 between points: nothing
  EXPECT_TRUE(out.empty());
  index.within_radius(m, {0, 0, 0}, -1.0, out);  // negative radius: nothing
  EXPECT_TRUE(out.empty());
}

TEST(PointIndex, DuplicatePoints) {
  PointModel m = random_cloud(300, 5);
  // A heavy duplicate (more copies than a leaf holds) and scattered pairs.
  const Vec3 heavy{0.25, -0.5, 0.125};
  std::vector<std::uint32_t> heavy_ids;
  for (int c = 0; c < 40; ++c) {
    heavy_ids.push_back(static_cast<std::uint32_t>(m.size()));
    m.push_back(heavy);
  }
  for (std::uint32_t i = 0; i < 300; i += 10) m.push_back(m.position(i));
  const PointIndex index(m);

  const PointIndex::Nearest n = index.nearest(m, heavy);
  EXPECT_EQ(n.index, heavy_ids.front());  // ties go to the smallest index
  EXPECT_EQ(n.distance, 0.0);
  std::vector<std::uint32_t> out;
  out.reserve(kOutCapacity);  // within_radius never grows it
  index.within_radius(m, heavy, 0.0, out);
  EXPECT_EQ(out, heavy_ids);
  for (std::uint32_t i = 0; i < 300; i += 10) {
    EXPECT_EQ(index.nearest(m, m.position(i)).index, i);
    index.within_radius(m, m.position(i), 0.0, out);
    EXPECT_EQ(out, oracle_within(m, m.position(i), 0.0));
    EXPECT_GE(out.size(), 2u);
  }
  for (const Vec3& q : random_queries(100, 8, 1.2)) {
    expect_nearest_matches_oracle(index, m, q, 0.0);
    index.within_radius(m, q, 0.2, out);
    EXPECT_EQ(out, oracle_within(m, q, 0.2));
  }
}

TEST(PointIndex, AllPointsIdentical) {
  PointModel m;
  for (int i = 0; i < 100; ++i) m.push_back({1, 1, 1});
  const PointIndex index(m);
  EXPECT_EQ(index.nearest(m, {0, 0, 0}).index, 0u);
  std::vector<std::uint32_t> out;
  out.reserve(kOutCapacity);  // within_radius never grows it
  index.within_radius(m, {1, 1, 1}, 0.0, out);
  EXPECT_EQ(out.size(), 100u);
}

TEST(PointIndex, ExactAfterBoundedDrift) {
  // Drift comparable to the point spacing (~0.06), so the current nearest point and the
  // current neighbourhoods really differ from the snapshot's.
  PointModel m = random_cloud(5000, 2024);
  const PointIndex index(m);
  const PointModel snapshot = m;
  std::size_t nearest_changed = 0;
  std::size_t neighbourhood_changed = 0;
  std::vector<std::uint32_t> out;
  out.reserve(kOutCapacity);  // within_radius never grows it
  for (const double drift : {0.001, 0.03, 0.1, 0.5}) {
    m = snapshot;
    const double moved = displace(m, drift, static_cast<std::uint32_t>(drift * 1e4));
    ASSERT_LE(moved, drift + 1e-6);  // float storage adds at most an ulp or so
    for (const Vec3& q : random_queries(300, 11, 1.3)) {
      expect_nearest_matches_oracle(index, m, q, moved);
      if (index.nearest(m, q, moved).index != index.nearest(snapshot, q).index) ++nearest_changed;
      for (const double radius : {0.0, 0.05, 0.2}) {
        index.within_radius(m, q, radius, out, moved);
        const std::vector<std::uint32_t> want = oracle_within(m, q, radius);
        EXPECT_EQ(out, want) << "drift " << drift << " radius " << radius;
        if (want != oracle_within(snapshot, q, radius)) ++neighbourhood_changed;
      }
    }
  }
  EXPECT_GT(nearest_changed, 200u);  // the test would catch a search that ignored drift
  EXPECT_GT(neighbourhood_changed, 200u);
}

TEST(PointIndex, LargeBallsAfterBoundedDriftAreExact) {
  // Balls of many spacings hold whole subtrees, which the query takes without testing their
  // points: that is exact only while every such subtree lies within radius - drift of q, so
  // the points moved up to the drift (a fifth of them by all of it) must still answer exactly,
  // including those that moved across the sphere of radius - drift.
  PointModel m = random_cloud(6000, 77);
  const PointIndex index(m);
  const PointModel snapshot = m;
  std::vector<std::uint32_t> out;
  out.reserve(kOutCapacity);
  std::size_t changed = 0;
  for (const double drift : {0.0, 0.01, 0.05, 0.2, 0.7}) {
    m = snapshot;
    const double moved = drift > 0.0 ? displace(m, drift, static_cast<std::uint32_t>(1 + drift * 1e3)) : 0.0;
    for (const Vec3& q : random_queries(60, 78, 1.2)) {
      for (const double radius : {0.3, 0.6, 1.1}) {
        EXPECT_TRUE(index.within_radius(m, q, radius, out, moved));
        const std::vector<std::uint32_t> want = oracle_within(m, q, radius);
        EXPECT_EQ(out, want) << "drift " << drift << " radius " << radius;
        if (want != oracle_within(snapshot, q, radius)) ++changed;
      }
    }
  }
  EXPECT_GT(changed, 500u);  // the moves really change the answers
  // The whole cloud in one ball, after the drift: every point, once.
  index.within_radius(m, {0, 0, 0}, 10.0, out, 0.7);
  EXPECT_EQ(out.size(), m.size());
}

TEST(PointIndex, DriftMovesTheNearestPointAway) {
  // Snapshot: a is nearest to the origin. After moving a away and b closer (each by exactly
  // `drift`), b is. A search ignoring drift would stop after a.
  PointModel m = random_cloud(2000, 3, 10.0);
  for (std::size_t i = 0; i < m.size(); ++i) {
    if (norm(m.position(i)) < 3.0) m.set_position(i, m.position(i) * (3.0 / norm(m.position(i))));
  }
  const std::uint32_t a = static_cast<std::uint32_t>(m.size());
  m.push_back({1.0, 0.0, 0.0});
  const std::uint32_t b = a + 1;
  m.push_back({0.0, 0.0, -1.5});
  const PointIndex index(m);
  EXPECT_EQ(index.nearest(m, {0, 0, 0}).index, a);
  m.set_position(a, {2.0, 0.0, 0.0});
  m.set_position(b, {0.0, 0.0, -0.5});
  const PointIndex::Nearest n = index.nearest(m, {0, 0, 0}, 1.0);
  EXPECT_EQ(n.index, b);
  EXPECT_DOUBLE_EQ(n.distance, 0.5);
  std::vector<std::uint32_t> out;
  out.reserve(kOutCapacity);  // within_radius never grows it
  index.within_radius(m, {0, 0, 0}, 0.75, out, 1.0);
  EXPECT_EQ(out, std::vector<std::uint32_t>{b});
}

TEST(PointIndex, RebuildTracksTheModel) {
  PointModel m = random_cloud(3000, 77);
  PointIndex index(m);
  displace(m, 0.2, 78);
  index.rebuild(m);
  for (const Vec3& q : random_queries(200, 79, 1.2)) expect_nearest_matches_oracle(index, m, q, 0.0);
  m = random_cloud(100, 80);  // a different size entirely
  index.rebuild(m);
  EXPECT_EQ(index.size(), 100u);
  for (const Vec3& q : random_queries(50, 81, 1.2)) expect_nearest_matches_oracle(index, m, q, 0.0);
}

TEST(PointIndex, MovedIndexKeepsWorking) {
  const PointModel m = random_cloud(1000, 90);
  PointIndex source(m);
  PointIndex moved(std::move(source));
  PointIndex assigned;
  assigned = std::move(moved);
  EXPECT_EQ(assigned.size(), 1000u);
  for (const Vec3& q : random_queries(50, 91, 1.2)) expect_nearest_matches_oracle(assigned, m, q, 0.0);
}

TEST(PointIndex, WithinRadiusDoesNotReallocateWithinCapacity) {
  const PointModel m = random_cloud(3000, 55);
  const PointIndex index(m);
  std::vector<std::uint32_t> out;
  out.reserve(m.size());
  const std::uint32_t* data = out.data();
  for (const Vec3& q : random_queries(50, 56, 1.0)) {
    index.within_radius(m, q, 0.5, out, 0.05);
    EXPECT_EQ(out.data(), data);
    EXPECT_EQ(out.capacity(), m.size());
  }
  // Too little capacity: never grown (the tick must not allocate), and said so. What fits is
  // a subset of the true neighbourhood.
  std::vector<std::uint32_t> small;
  small.reserve(2);
  const std::vector<std::uint32_t> truth = oracle_within(m, {0, 0, 0}, 0.5);
  ASSERT_GT(truth.size(), small.capacity());
  EXPECT_FALSE(index.within_radius(m, {0, 0, 0}, 0.5, small));
  EXPECT_EQ(small.capacity(), 2u);
  EXPECT_EQ(small.size(), 2u);
  for (std::uint32_t i : small) EXPECT_TRUE(std::binary_search(truth.begin(), truth.end(), i)) << i;
  // With room for every match the answer is complete, and says so.
  small.reserve(m.size());
  EXPECT_TRUE(index.within_radius(m, {0, 0, 0}, 0.5, small));
  EXPECT_EQ(small, truth);
}

TEST(PointIndex, KNearestMatchesBruteForce) {
  const PointModel m = random_cloud(2000, 66);
  const PointIndex index(m);
  std::vector<std::uint32_t> ids;
  std::vector<double> d2;
  for (const Vec3& q : random_queries(100, 67, 1.2)) {
    std::vector<double> all(m.size());
    for (std::size_t i = 0; i < m.size(); ++i) all[i] = squared_distance(m, i, q);
    std::sort(all.begin(), all.end());
    index.k_nearest(q, 12, ids, d2);
    ASSERT_EQ(ids.size(), 12u);
    ASSERT_EQ(d2.size(), 12u);
    EXPECT_TRUE(std::is_sorted(d2.begin(), d2.end()));
    for (std::size_t j = 0; j < 12; ++j) {
      EXPECT_NEAR(d2[j], all[j], 1e-12);
      EXPECT_NEAR(d2[j], squared_distance(m, ids[j], q), 1e-12);
    }
  }
  index.k_nearest({0, 0, 0}, 0, ids, d2);
  EXPECT_TRUE(ids.empty());
  index.k_nearest({0, 0, 0}, 5000, ids, d2);  // more than there are
  EXPECT_EQ(ids.size(), m.size());
}

TEST(PointIndex, KNearestUsesTheSnapshot) {
  PointModel m = random_cloud(500, 12);
  const PointIndex index(m);
  std::vector<std::uint32_t> ids;
  std::vector<double> d2;
  const Vec3 p = m.position(17);
  m.set_position(17, {50, 50, 50});  // moving the model does not move the snapshot
  index.k_nearest(p, 1, ids, d2);
  ASSERT_EQ(ids.size(), 1u);
  EXPECT_EQ(ids[0], 17u);
  EXPECT_EQ(d2[0], 0.0);
}

TEST(PointIndex, AModelOfAnotherSizeFindsNothingAndNeverReadsPastItsArrays) {
  // The queries run in the tick and cannot throw: a model the index was not built over is
  // recognised (indexes()) and answered with "nothing", never an out-of-range read.
  const PointModel m = random_cloud(100, 1);
  const PointIndex index(m);
  const PointModel other = random_cloud(99, 1);
  EXPECT_TRUE(index.indexes(m));
  EXPECT_FALSE(index.indexes(other));
  std::vector<std::uint32_t> out;
  out.reserve(kOutCapacity);  // within_radius never grows it
  EXPECT_EQ(index.nearest(other, {0, 0, 0}).index, PointIndex::kNoPoint);
  EXPECT_FALSE(index.within_radius(other, {0, 0, 0}, 1.0, out));
  EXPECT_TRUE(out.empty());
}

TEST(PointIndex, ConcurrentReadersAgreeWithTheOracle) {
  PointModel m = random_cloud(4000, 31);
  const PointIndex index(m);
  const double moved = displace(m, 0.05, 32);
  const std::vector<Vec3> queries = random_queries(200, 33, 1.2);
  std::vector<std::vector<std::uint32_t>> want(queries.size());
  std::vector<std::uint32_t> want_nearest(queries.size());
  for (std::size_t i = 0; i < queries.size(); ++i) {
    want[i] = oracle_within(m, queries[i], 0.15);
    want_nearest[i] = index.nearest(m, queries[i], moved).index;
  }
  std::vector<int> failures(4, 0);
  std::vector<std::thread> readers;
  for (int t = 0; t < 4; ++t) {
    readers.emplace_back([&, t] {
      std::vector<std::uint32_t> out;
      out.reserve(kOutCapacity);  // within_radius never grows it
      out.reserve(m.size());
      for (int round = 0; round < 5; ++round) {
        for (std::size_t i = 0; i < queries.size(); ++i) {
          index.within_radius(m, queries[i], 0.15, out, moved);
          if (out != want[i]) ++failures[t];
          if (index.nearest(m, queries[i], moved).index != want_nearest[i]) ++failures[t];
        }
      }
    });
  }
  for (std::thread& r : readers) r.join();
  for (int t = 0; t < 4; ++t) EXPECT_EQ(failures[t], 0) << "reader " << t;
}

// --- the moved list (track_moved): with it, queries passed no drift at all must still be exact
// on a model deformed stroke after stroke; without it, the same strokes and queries must be
// seen going wrong, so these checks can fail ---

// The definition: the closest current position, ties to the smallest index.
PointIndex::Nearest brute_nearest(const PointModel& m, const Vec3& q) {
  std::uint32_t best = PointIndex::kNoPoint;
  double best_squared = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < m.size(); ++i) {
    const double d2 = squared_distance(m, i, q);
    if (d2 < best_squared) {
      best_squared = d2;
      best = static_cast<std::uint32_t>(i);
    }
  }
  return {best, std::sqrt(best_squared)};
}

// The sphere with its first 300 points repeated, so that nearest() meets exact ties.
PointModel sphere_with_ties() {
  PointModel m = make_sphere(20000);
  for (std::size_t i = 0; i < 300; ++i) m.push_back(m.position(i));
  return m;
}

// One "frame": the points within `radius` of a random model point are pushed inward by up to
// `depth` (a smooth bump), and the index is told which ones were written. Returns them.
std::vector<std::uint32_t> press(PointModel& m, PointIndex& index, std::mt19937& rng, double radius, double depth) {
  std::uniform_int_distribution<std::size_t> pick(0, m.size() - 1);
  const Vec3 centre = m.position(pick(rng));
  std::vector<std::uint32_t> moved;
  for (std::size_t i = 0; i < m.size(); ++i) {
    const double r2 = squared_distance(m, i, centre) / (radius * radius);
    if (r2 >= 1.0) continue;
    const Vec3 p = m.position(i);
    m.set_position(i, p - normalized(p) * (depth * (1.0 - r2)) + Vec3{0.3, 0.0, 0.1} * (depth * (1.0 - r2)));
    moved.push_back(static_cast<std::uint32_t>(i));
  }
  index.note_moved(m, moved, false);
  return moved;
}

// A nearest() answer agrees with brute force: a point as near as the nearest and the same
// distance, to 1e-12 relative. Not bit for bit: the library and a test may be compiled with
// other flags (the minimal pass builds tests at -O0), and a fused multiply-add moves the last
// bit, which also decides near-ties between distinct points. A stale answer is off by far more.
bool same_nearest(const PointModel& m, const Vec3& q, const PointIndex::Nearest& got, const PointIndex::Nearest& want) {
  if (got.index == PointIndex::kNoPoint || want.index == PointIndex::kNoPoint) return got.index == want.index;
  const double slack = 1e-12 * want.distance + 1e-300;
  return std::sqrt(squared_distance(m, got.index, q)) <= want.distance + slack &&
         std::abs(got.distance - want.distance) <= slack;
}

// press()'s largest move for a depth, with room for the float rounding of the new positions.
double press_move_bound(double depth) { return depth * (1.0 + std::hypot(0.3, 0.1)) + 1e-6; }

// Queries near the moved points and at random, all answered with drift 0.
struct Misses {
  int nearest = 0, within = 0, queries = 0;
};

Misses check_queries(const PointModel& m, const PointIndex& index, std::mt19937& rng,
                     const std::vector<std::uint32_t>& near) {
  std::uniform_real_distribution<double> jitter(-0.03, 0.03);
  std::uniform_int_distribution<std::size_t> pick(0, near.size() - 1);
  std::vector<std::uint32_t> found;
  found.reserve(kOutCapacity);
  Misses misses;
  for (int k = 0; k < 60; ++k) {
    const Vec3 q = m.position(near[pick(rng)]) + Vec3{jitter(rng), jitter(rng), jitter(rng)};
    const PointIndex::Nearest got = index.nearest(m, q, 0.0);
    const PointIndex::Nearest want = brute_nearest(m, q);
    misses.nearest += !same_nearest(m, q, got, want);
    EXPECT_TRUE(index.within_radius(m, q, 0.06, found, 0.0));
    misses.within += found != oracle_within(m, q, 0.06);
    ++misses.queries;
  }
  return misses;
}

TEST(MovedPointsIndex, QueriesWithNoDriftStayExactStrokeAfterStroke) {
  PointModel m = sphere_with_ties();
  PointIndex index(m);
  index.track_moved(1 << 16);
  std::mt19937 rng(7);
  int nearest_misses = 0, within_misses = 0;
  for (int frame = 0; frame < 40; ++frame) {
    const std::vector<std::uint32_t> moved = press(m, index, rng, 0.12, 0.03);
    ASSERT_FALSE(moved.empty());
    ASSERT_TRUE(index.moved_complete());
    const Misses misses = check_queries(m, index, rng, moved);
    nearest_misses += misses.nearest;
    within_misses += misses.within;
  }
  EXPECT_EQ(nearest_misses, 0);
  EXPECT_EQ(within_misses, 0);
  EXPECT_GT(index.moved_count(), 0u);
}

TEST(MovedPointsIndex, WithoutTheListTheSameStrokesNeedTheDrift) {
  // The control: the same strokes and queries on an index without the list, passed no drift,
  // give wrong answers, so the test above would see a list that does not work.
  PointModel m = sphere_with_ties();
  PointIndex index(m);
  std::mt19937 rng(7);
  int misses = 0;
  for (int frame = 0; frame < 40; ++frame) {
    const std::vector<std::uint32_t> moved = press(m, index, rng, 0.12, 0.03);
    const Misses found = check_queries(m, index, rng, moved);
    misses += found.nearest + found.within;
  }
  EXPECT_GT(misses, 0);
  EXPECT_FALSE(index.moved_complete());
}

TEST(MovedPointsIndex, AnOverflowingListFallsBackOnTheDrift) {
  PointModel m = sphere_with_ties();
  PointIndex index(m);
  index.track_moved(50);  // far fewer than one press moves
  std::mt19937 rng(11);
  double drift = 0.0;
  for (int frame = 0; frame < 10; ++frame) {
    const PointModel before = m;
    const std::vector<std::uint32_t> moved = press(m, index, rng, 0.12, 0.03);
    for (std::uint32_t i : moved) drift = std::max(drift, norm(m.position(i) - before.position(i)));
  }
  EXPECT_FALSE(index.moved_complete());
  // Exact again with the drift, as without a list. (The drift summed over frames bounds every
  // point's distance from its snapshot position; the largest single move is used here, times
  // the frames, which is such a sum.)
  std::vector<std::uint32_t> found;
  found.reserve(kOutCapacity);
  const double bound = 10.0 * drift;
  for (int k = 0; k < 200; ++k) {
    const Vec3 q = m.position(static_cast<std::size_t>(k) * 97 % m.size());
    const PointIndex::Nearest got = index.nearest(m, q, bound);
    EXPECT_TRUE(same_nearest(m, q, got, brute_nearest(m, q)));
    EXPECT_TRUE(index.within_radius(m, q, 0.05, found, bound));
    EXPECT_EQ(found, oracle_within(m, q, 0.05));
  }
  // A snapshot of the positions as they are now clears it.
  index.rebuild(m);
  EXPECT_TRUE(index.moved_complete());
  EXPECT_EQ(index.moved_count(), 0u);
}

TEST(MovedPointsIndex, ASwappedInIndexKeepsOnlyThePointsMovedSinceItsSnapshot) {
  // As the station's rebuilder does: a snapshot is taken mid-stroke, built elsewhere, more
  // frames run on the old index, then the new one is swapped in and takes over the list.
  PointModel m = sphere_with_ties();
  PointIndex index(m);
  index.track_moved(1 << 16);
  std::mt19937 rng(3);
  for (int frame = 0; frame < 10; ++frame) press(m, index, rng, 0.12, 0.03);
  const PointModel snapshot = m;
  PointIndex fresh(snapshot);
  std::vector<std::uint32_t> last;
  for (int frame = 0; frame < 5; ++frame) last = press(m, index, rng, 0.12, 0.03);

  std::swap(index, fresh);
  index.take_moved(fresh, m);
  ASSERT_TRUE(index.moved_complete());
  std::size_t differ = 0;
  for (std::size_t i = 0; i < m.size(); ++i) {
    differ += m.x[i] != snapshot.x[i] || m.y[i] != snapshot.y[i] || m.z[i] != snapshot.z[i];
  }
  EXPECT_EQ(index.moved_count(), differ);
  EXPECT_GT(differ, 0u);
  EXPECT_EQ(fresh.moved_count(), 0u);  // the old tree, to be freed, holds no list any more

  int misses = 0;
  for (int frame = 0; frame < 10; ++frame) {
    last = press(m, index, rng, 0.12, 0.03);
    const Misses found = check_queries(m, index, rng, last);
    misses += found.nearest + found.within;
  }
  EXPECT_EQ(misses, 0);
}

TEST(MovedPointsIndex, QueriesAboveAndBelowADeepDentAreExact) {
  // One spot pressed frame after frame: the snapshot's surface then lies between a query above
  // the dent and the points it should find, and the tree must leave the dent's subtrees, whose
  // points are all listed, to the list. Queries above the dent at many heights, inside the
  // model under it, and across the whole model, against brute force; then after a swapped-in
  // index took over the list (its subtrees counted afresh) and after forgetting it.
  PointModel m = make_sphere(20000);
  PointIndex index(m);
  index.track_moved(1 << 16);
  const Vec3 top{0.0, 0.0, 1.0};
  for (int frame = 0; frame < 12; ++frame) {
    std::vector<std::uint32_t> moved;
    for (std::size_t i = 0; i < m.size(); ++i) {
      const double r2 = squared_distance(m, i, top) / (0.2 * 0.2);
      if (r2 >= 1.0) continue;
      m.set_position(i, m.position(i) - Vec3{0.0, 0.0, 0.03 * (1.0 - r2)});
      moved.push_back(static_cast<std::uint32_t>(i));
    }
    index.note_moved(m, moved, false);
    // The first query that meets moved points makes the index keep its subtree counts from the
    // next frame on, so the checks below use them.
    if (frame == 0) (void)index.nearest(m, top, 0.0);
  }
  ASSERT_TRUE(index.moved_complete());
  std::vector<std::uint32_t> found;
  found.reserve(kOutCapacity);
  auto check = [&](const char* when) {
    int misses = 0, queries = 0;
    for (double height = -0.6; height <= 0.6; height += 0.025) {
      for (const double dx : {0.0, 0.05, 0.13}) {
        const Vec3 q{dx, 0.01, 1.0 + height};
        misses += !same_nearest(m, q, index.nearest(m, q, 0.0), brute_nearest(m, q));
        for (const double radius : {0.06, 0.4}) {
          EXPECT_TRUE(index.within_radius(m, q, radius, found, 0.0));
          misses += found != oracle_within(m, q, radius);
        }
        ++queries;
      }
    }
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> anywhere(-1.6, 1.6);
    for (int k = 0; k < 100; ++k, ++queries) {
      const Vec3 q{anywhere(rng), anywhere(rng), anywhere(rng)};
      misses += !same_nearest(m, q, index.nearest(m, q, 0.0), brute_nearest(m, q));
      EXPECT_TRUE(index.within_radius(m, q, 0.1, found, 0.0));
      misses += found != oracle_within(m, q, 0.1);
    }
    EXPECT_EQ(misses, 0) << when << ", " << queries << " queries";
  };
  check("pressed");
  // A snapshot of the dent half way, swapped in: it takes over the points that still differ.
  PointModel half = make_sphere(20000);
  for (std::size_t i = 0; i < half.size(); ++i) half.set_position(i, (half.position(i) + m.position(i)) * 0.5);
  PointIndex fresh(half);
  std::swap(index, fresh);
  index.take_moved(fresh, m);
  ASSERT_TRUE(index.moved_complete());
  check("after the swap");
  m = half;
  index.forget_moved();
  check("back at the snapshot");
}

TEST(MovedPointsIndex, AListLongerThanOneCatchUpIsCountedOverSeveralFramesAndStaysExact) {
  // The index brings its subtree counts up to the list at most 8,192 points a frame (so that a
  // swapped-in index with a long list does not stall a tick); queries in between skip listed
  // points one by one and must be as exact as before and after.
  PointModel m = make_sphere(40000);
  PointIndex index(m);
  index.track_moved(1 << 16);
  std::mt19937 rng(13);
  for (int frame = 0; frame < 40; ++frame) press(m, index, rng, 0.3, 0.02);
  ASSERT_TRUE(index.moved_complete());
  ASSERT_GT(index.moved_count(), 2u * 8192u);  // three catch-ups or more
  int misses = 0;
  for (int frame = 0; frame < 6; ++frame) {
    const std::vector<std::uint32_t> moved = press(m, index, rng, 0.3, 0.02);
    const Misses found = check_queries(m, index, rng, moved);  // the first ones ask for the counts
    misses += found.nearest + found.within;
  }
  EXPECT_EQ(misses, 0);
}

TEST(MovedPointsIndex, AnUndoneFrameIsToldAndStaysExact) {
  // An undo writes old positions back: the points keep their place in the list (it only ever
  // covers), and queries near both the undone and the kept positions stay exact.
  PointModel m = sphere_with_ties();
  PointIndex index(m);
  index.track_moved(1 << 16);
  std::mt19937 rng(5);
  int misses = 0;
  for (int frame = 0; frame < 20; ++frame) {
    const PointModel before = m;
    const std::vector<std::uint32_t> moved = press(m, index, rng, 0.15, 0.05);
    if (frame % 2 == 0) {
      for (std::uint32_t i : moved) m.set_position(i, before.position(i));
      index.note_moved(m, moved, false);
    }
    const Misses found = check_queries(m, index, rng, moved);
    misses += found.nearest + found.within;
  }
  EXPECT_EQ(misses, 0);
  // Every point back where the snapshot had it: forgetting the list keeps the queries exact.
  const PointModel base = sphere_with_ties();
  m = base;
  index.note_moved(m, {}, true);
  EXPECT_FALSE(index.moved_complete());
  index.forget_moved();
  EXPECT_TRUE(index.moved_complete());
  std::vector<std::uint32_t> all(m.size());
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = static_cast<std::uint32_t>(i);
  const Misses found = check_queries(m, index, rng, all);
  EXPECT_EQ(found.nearest + found.within, 0);
}

TEST(MovedPointsIndex, AHintNeverChangesTheAnswer) {
  // nearest()'s hint only bounds the search from the start. Under a dent (the moved list in use)
  // and under a drift (the widened tree), with hints at the answer, beside it, across the model,
  // on a tied duplicate with the larger index, and out of range: every answer is the unhinted
  // one, bit for bit, and brute force's.
  PointModel m = sphere_with_ties();
  PointIndex listed(m);
  listed.track_moved(1 << 16);
  PointIndex widened(m);
  std::mt19937 rng(21);
  double drift = 0.0;
  for (int frame = 0; frame < 10; ++frame) {
    const std::vector<std::uint32_t> moved = press(m, listed, rng, 0.25, 0.05);
    drift += press_move_bound(0.05);
    (void)listed.nearest(m, m.position(moved.front()), 0.0);  // the list's counts from now on
  }
  ASSERT_TRUE(listed.moved_complete());
  const auto n = static_cast<std::uint32_t>(m.size());
  std::uniform_int_distribution<std::uint32_t> pick(0, n - 1);
  std::uniform_real_distribution<double> jitter(-0.05, 0.05);
  int queries = 0, brute_misses = 0;
  for (int k = 0; k < 200; ++k) {
    const Vec3 q = m.position(pick(rng)) * (k % 2 == 0 ? 1.0 : 1.2) + Vec3{jitter(rng), jitter(rng), jitter(rng)};
    const PointIndex::Nearest want = brute_nearest(m, q);
    const std::uint32_t tied = want.index < 300 ? 20000 + want.index : want.index;  // its duplicate
    for (const PointIndex* index : {&listed, &widened}) {
      const double d = index == &listed ? 0.0 : drift;
      const PointIndex::Nearest plain = index->nearest(m, q, d);
      brute_misses += !same_nearest(m, q, plain, want);
      for (const std::uint32_t hint :
           {want.index, tied, pick(rng), (want.index + 1) % n, PointIndex::kNoPoint, n + 5}) {
        const PointIndex::Nearest hinted = index->nearest(m, q, d, hint);
        ASSERT_EQ(hinted.index, plain.index) << "query " << k << ", hint " << hint;
        ASSERT_EQ(hinted.distance, plain.distance) << "query " << k << ", hint " << hint;
        ++queries;
      }
    }
  }
  EXPECT_EQ(brute_misses, 0);
  EXPECT_EQ(queries, 200 * 2 * 6);
  // A non-finite query finds nothing, whatever the hint.
  const Vec3 nan_query{std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0};
  for (const PointIndex* index : {&listed, &widened}) {
    EXPECT_EQ(index->nearest(m, nan_query, drift, 0).index, PointIndex::kNoPoint);
  }
}

TEST(MovedPointsIndex, PointsSetAsideUntilTheListIsWantedAreListedOnceAndQueriesStayExact) {
  // With a min_drift, a write the next queries will not consult the list for is set aside:
  // counted once however often it is told, listed by prepare_queries(). Queries at a drift that
  // would consult the list stay exact before (they widen by the drift) and after it.
  PointModel m = sphere_with_ties();
  PointIndex index(m);
  constexpr double kMinDrift = 0.2;
  index.track_moved(1 << 16, kMinDrift);
  std::mt19937 rng(41);
  PointIndex untold;  // press() tells this one; `index` is told below
  double drift = 0.0;
  std::vector<std::uint32_t> all_moved;
  for (int frame = 0; frame < 8; ++frame) {
    const std::vector<std::uint32_t> moved = press(m, untold, rng, 0.2, 0.03);
    drift += press_move_bound(0.03);
    index.note_moved(m, moved, false, /*next_drift=*/0.0);  // queries below the list's drift
    index.note_moved(m, moved, false, 0.0);                 // told twice, counted once
    all_moved.insert(all_moved.end(), moved.begin(), moved.end());
  }
  std::sort(all_moved.begin(), all_moved.end());
  all_moved.erase(std::unique(all_moved.begin(), all_moved.end()), all_moved.end());
  ASSERT_GE(drift, kMinDrift);
  EXPECT_EQ(index.moved_count(), all_moved.size());
  std::vector<std::uint32_t> found;
  found.reserve(kOutCapacity);
  std::uniform_int_distribution<std::size_t> pick(0, all_moved.size() - 1);
  auto misses = [&] {
    int n = 0;
    for (int k = 0; k < 40; ++k) {
      const Vec3 q = m.position(all_moved[pick(rng)]) * 1.01;
      n += !same_nearest(m, q, index.nearest(m, q, drift), brute_nearest(m, q));
      EXPECT_TRUE(index.within_radius(m, q, 0.06, found, drift));
      n += found != oracle_within(m, q, 0.06);
    }
    return n;
  };
  EXPECT_EQ(misses(), 0) << "set aside";
  index.prepare_queries(m, drift);
  EXPECT_EQ(index.moved_count(), all_moved.size());
  EXPECT_EQ(misses(), 0) << "listed";
  // Listed, the answers no longer depend on the drift passed: a far too small one (above the
  // list's threshold) still finds the moved points.
  const Vec3 q = m.position(all_moved.front());
  EXPECT_TRUE(same_nearest(m, q, index.nearest(m, q, kMinDrift), brute_nearest(m, q)));
}

}  // namespace
}  // namespace sculpt::deform
