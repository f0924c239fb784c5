#include "sculpt/deform/model_scale.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace sculpt::deform {
namespace {

// Neighbours asked for first: the point itself, a copy or two, and a true neighbour.
constexpr std::size_t kFirstNeighbours = 4;
// Widening (by doubling) stops here: a sampled point with more copies than this is skipped, so
// one large stack of duplicates cannot turn each query into a sort of the whole model.
constexpr std::size_t kMaxNeighbours = 256;

// Distance from p to its nearest snapshot point at a distance > 0, or 0 when every one of the
// nearest `limit` points coincides with p.
double nearest_distinct(const PointIndex& index, const Vec3& p, std::size_t limit,
                        std::vector<std::uint32_t>& neighbours, std::vector<double>& squared) {
  for (std::size_t k = std::min(kFirstNeighbours, limit);; k = std::min(2 * k, limit)) {
    index.k_nearest(p, k, neighbours, squared);
    // Closest first: the first nonzero distance is the nearest distinct neighbour.
    for (const double d2 : squared) {
      if (d2 > 0.0) return std::sqrt(d2);
    }
    if (k >= limit || squared.size() < k) return 0.0;
  }
}

bool all_coincide(const PointModel& m) {
  for (std::size_t i = 1; i < m.size(); ++i) {
    if (m.x[i] != m.x[0] || m.y[i] != m.y[0] || m.z[i] != m.z[0]) return false;
  }
  return true;
}

// One point per distinct position (attributes other than the position dropped).
PointModel distinct_positions(const PointModel& m) {
  std::vector<std::uint32_t> order(m.size());
  std::iota(order.begin(), order.end(), 0u);
  const auto key = [&m](std::uint32_t i) { return std::array<float, 3>{m.x[i], m.y[i], m.z[i]}; };
  std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return key(a) < key(b); });
  order.erase(
      std::unique(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return key(a) == key(b); }),
      order.end());
  PointModel distinct;
  for (const std::uint32_t i : order) distinct.push_back(m.position(i));
  return distinct;
}

double median(std::vector<double>& values) {
  const std::size_t half = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(half), values.end());
  const double upper = values[half];
  if (values.size() % 2 == 1) return upper;
  // nth_element leaves the smaller half in front: its largest is the lower middle value.
  const double lower = *std::max_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(half));
  return 0.5 * (lower + upper);
}

}  // namespace

TypicalSpacing typical_spacing(const PointModel& model, const PointIndex& index, std::size_t samples) {
  const std::size_t n = model.size();
  if (samples == 0) throw std::invalid_argument("typical spacing: needs at least one sample");
  if (index.size() != n) throw std::invalid_argument("typical spacing: the index is not built over this model");
  if (n == 0) throw std::invalid_argument("the model has no points: no length scale");
  if (all_coincide(model)) {
    std::ostringstream text;
    text << "the model's points all coincide: no length scale (";
    if (n == 1) {
      text << "it has a single point)";
    } else {
      text << "all " << n << " are at (" << model.x[0] << ", " << model.y[0] << ", " << model.z[0] << "))";
    }
    throw std::invalid_argument(text.str());
  }
  const std::size_t m = std::min(n, samples);
  std::vector<double> distances;
  distances.reserve(m);
  std::vector<std::uint32_t> neighbours;
  std::vector<double> squared;
  for (std::size_t k = 0; k < m; ++k) {
    const std::size_t i = k * n / m;  // evenly spread over the file's order; no overflow below 2^40 points
    const double d = nearest_distinct(index, model.position(i), std::min(n, kMaxNeighbours), neighbours, squared);
    if (d > 0.0) distances.push_back(d);
  }
  if (distances.empty()) {
    // Every sample sits in a stack of more than kMaxNeighbours copies, yet not all points
    // coincide: measure on one copy of each position instead (a sort, but no quadratic search).
    const PointModel distinct = distinct_positions(model);
    return typical_spacing(distinct, PointIndex(distinct), samples);
  }
  TypicalSpacing result;
  result.statistic = "median nearest-neighbour distance over distinct points, " + std::to_string(distances.size()) +
                     (distances.size() == 1 ? " sample" : " samples");
  result.value = median(distances);
  return result;
}

std::size_t median_ball_count(const PointModel& model, const PointIndex& index, double radius) {
  const std::size_t n = model.size();
  if (n == 0) return 0;
  const std::size_t samples = std::min<std::size_t>(n, 64);
  std::vector<std::size_t> counts;
  std::vector<std::uint32_t> found;
  found.reserve(n);  // within_radius fills up to the capacity and never grows it
  for (std::size_t k = 0; k < samples; ++k) {
    index.within_radius(model, model.position(k * n / samples), radius, found);
    counts.push_back(found.size());
  }
  std::nth_element(counts.begin(), counts.begin() + static_cast<std::ptrdiff_t>(samples / 2), counts.end());
  return counts[samples / 2];
}

}  // namespace sculpt::deform
