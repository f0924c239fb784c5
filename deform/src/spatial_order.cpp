#include "sculpt/deform/spatial_order.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

namespace sculpt::deform {
namespace {

constexpr int kBitsPerAxis = 21;  // three axes' bits fill 63 of a 64-bit key

// v's low 21 bits spread to every third bit (bit b to bit 3b).
std::uint64_t spread_bits(std::uint64_t v) {
  std::uint64_t r = 0;
  for (int b = 0; b < kBitsPerAxis; ++b) r |= ((v >> b) & 1u) << (3 * b);
  return r;
}

template <typename T>
void take(std::vector<T>& attribute, std::span<const std::uint32_t> order) {
  if (attribute.empty()) return;
  std::vector<T> out(order.size());
  for (std::size_t k = 0; k < order.size(); ++k) out[k] = attribute[order[k]];
  attribute = std::move(out);
}

}  // namespace

std::vector<std::uint32_t> spatial_order(const PointModel& model) {
  const std::size_t n = model.size();
  if (n == 0) return {};
  const auto [lo, hi] = model.bounding_box();
  const std::vector<float>* axes[3] = {&model.x, &model.y, &model.z};
  const double extent = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
  // One cube for all three axes, so a cell is as long in each: the order follows distance.
  const double cells = static_cast<double>((std::uint64_t{1} << kBitsPerAxis) - 1);
  const double scale = extent > 0.0 ? cells / extent : 0.0;
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keys(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::uint64_t key = 0;
    for (int a = 0; a < 3; ++a) {
      const double cell = std::clamp(std::floor((static_cast<double>((*axes[a])[i]) - lo[a]) * scale), 0.0, cells);
      key |= spread_bits(static_cast<std::uint64_t>(cell)) << a;
    }
    keys[i] = {key, static_cast<std::uint32_t>(i)};
  }
  std::sort(keys.begin(), keys.end());
  std::vector<std::uint32_t> order(n);
  for (std::size_t k = 0; k < n; ++k) order[k] = keys[k].second;
  return order;
}

PointModel reordered(const PointModel& model, std::span<const std::uint32_t> order) {
  const std::size_t n = model.size();
  if (order.size() != n) {
    throw std::invalid_argument("reordered: the order has " + std::to_string(order.size()) + " entries for " +
                                std::to_string(n) + " points");
  }
  // new_place[old] = where the old point goes; also proves the order a permutation.
  constexpr std::uint32_t kUnplaced = ~std::uint32_t{0};
  std::vector<std::uint32_t> new_place(n, kUnplaced);
  for (std::size_t k = 0; k < n; ++k) {
    const std::uint32_t i = order[k];
    if (i >= n || new_place[i] != kUnplaced) {
      throw std::invalid_argument("reordered: entry " + std::to_string(k) + " (" + std::to_string(i) +
                                  (i >= n ? ") is not a point" : ") repeats a point"));
    }
    new_place[i] = static_cast<std::uint32_t>(k);
  }
  PointModel out = model;
  for (std::vector<float>* a : {&out.x, &out.y, &out.z, &out.nx, &out.ny, &out.nz}) take(*a, order);
  for (std::vector<std::uint8_t>* a : {&out.red, &out.green, &out.blue, &out.alpha}) take(*a, order);
  for (std::uint32_t& corner : out.triangles) corner = new_place[corner];
  return out;
}

double neighbour_locality(const PointModel& model, const PointIndex& index, std::size_t samples) {
  constexpr std::size_t kNeighbours = 8;
  constexpr std::size_t kLine = 16;  // floats in a 64-byte cache line
  const std::size_t n = model.size();
  if (n <= kNeighbours || samples == 0) return 0.0;
  const std::size_t step = std::max<std::size_t>(1, n / samples);
  std::vector<std::uint32_t> found;
  std::vector<double> squared;
  std::size_t near = 0, pairs = 0;
  for (std::size_t i = 0; i < n; i += step) {
    index.k_nearest(model.position(i), kNeighbours + 1, found, squared);
    for (const std::uint32_t j : found) {
      if (j == i) continue;
      ++pairs;
      const std::size_t apart = j > i ? j - i : i - j;
      if (apart <= kLine) ++near;
    }
  }
  return pairs > 0 ? static_cast<double>(near) / static_cast<double>(pairs) : 0.0;
}

}  // namespace sculpt::deform
