#include "unlisted_tree.hpp"

namespace sculpt::deform {

void UnlistedTree::mark_listed(std::uint32_t i) noexcept {
  if (i >= leaf_of_.size()) return;
  std::uint32_t node = leaf_of_[i];
  if (node == kNone || unlisted_[node] == 0 || --unlisted_[node] > 0) return;
  for (node = parent_[node]; node != kNone; node = parent_[node]) {
    if (--unlisted_[node] > 0) return;
  }
}

// nanoflann's searchLevel: the nearer child first, then the farther one if the box distance,
// updated in the split's dimension only, can still beat the bound. A subtree whose points are
// all on the list is skipped whatever its distance.
template <bool kBySubtree, class Leaf>
void UnlistedTree::descend(std::uint32_t node, double min_distance, double* distances, const double* q,
                           const double& bound, Leaf& leaf) const noexcept {
  if (kBySubtree && unlisted_[node] == 0) return;
  const Node& n = nodes_[node];
  if (n.feature < 0) {
    leaf(n.first, n.second);
    return;
  }
  const int f = n.feature;
  const double value = q[f];
  const double below = value - static_cast<double>(n.low), above = value - static_cast<double>(n.high);
  std::uint32_t nearer = n.first, farther = n.second;
  double cut = above * above;
  if (below + above >= 0.0) {
    nearer = n.second;
    farther = n.first;
    cut = below * below;
  }
  descend<kBySubtree>(nearer, min_distance, distances, q, bound, leaf);
  const double saved = distances[f];
  min_distance = min_distance + cut - saved;
  distances[f] = cut;
  if (min_distance <= bound) descend<kBySubtree>(farther, min_distance, distances, q, bound, leaf);
  distances[f] = saved;
}

template <class Leaf>
void UnlistedTree::search(const double* q, const double& bound, bool by_subtree, Leaf& leaf) const noexcept {
  if (nodes_.empty()) return;
  double distances[3] = {0.0, 0.0, 0.0};
  double min_distance = 0.0;
  for (int d = 0; d < 3; ++d) {
    if (q[d] < low_[d]) distances[d] = (q[d] - low_[d]) * (q[d] - low_[d]);
    if (q[d] > high_[d]) distances[d] = (q[d] - high_[d]) * (q[d] - high_[d]);
    min_distance += distances[d];
  }
  if (by_subtree) {
    descend<true>(0, min_distance, distances, q, bound, leaf);
  } else {
    descend<false>(0, min_distance, distances, q, bound, leaf);
  }
}

void UnlistedTree::nearest(const float* xyz, const double* q, const MovedOverlay& list, bool by_subtree,
                           std::uint32_t& best, double& best_squared) const noexcept {
  double bound = widened_bound(best_squared);
  auto leaf = [&](std::uint32_t first, std::uint32_t end) {
    for (std::uint32_t k = first; k < end; ++k) {
      const std::uint32_t i = order_[k];
      if (list.contains(i)) continue;
      const float* p = xyz + 3 * static_cast<std::size_t>(i);
      const double d2 = squared_distance_to(p[0], p[1], p[2], q);
      if (d2 < best_squared || (d2 == best_squared && i < best)) {
        best_squared = d2;
        best = i;
        bound = widened_bound(d2);
      }
    }
  };
  search(q, bound, by_subtree, leaf);
}

bool UnlistedTree::within_radius(const float* xyz, const double* q, double radius_squared, const MovedOverlay& list,
                                 bool by_subtree, std::vector<std::uint32_t>& out) const noexcept {
  const double bound = widened_bound(radius_squared);
  bool complete = true;
  auto leaf = [&](std::uint32_t first, std::uint32_t end) {
    for (std::uint32_t k = first; k < end; ++k) {
      const std::uint32_t i = order_[k];
      if (list.contains(i)) continue;
      const float* p = xyz + 3 * static_cast<std::size_t>(i);
      if (squared_distance_to(p[0], p[1], p[2], q) > radius_squared) continue;
      if (out.size() < out.capacity()) {
        out.push_back(i);
      } else {
        complete = false;
      }
    }
  };
  search(q, bound, by_subtree, leaf);
  return complete;
}

}  // namespace sculpt::deform
