#include "unlisted_tree.hpp"

#include <algorithm>

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

void UnlistedTree::nearest(const double* q, const MovedOverlay& list, bool by_subtree, std::uint32_t& best,
                           double& best_squared) const noexcept {
  double bound = widened_bound(best_squared);
  auto leaf = [&](std::uint32_t first, std::uint32_t end) {
    for (std::uint32_t k = first; k < end; ++k) {
      const std::uint32_t i = order_[k];
      if (list.contains(i)) continue;
      const float* p = ordered_xyz_.data() + 3 * static_cast<std::size_t>(k);
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

bool UnlistedTree::within_radius(const double* q, double radius_squared, const MovedOverlay& list, bool by_subtree,
                                 std::vector<std::uint32_t>& out) const noexcept {
  const double bound = widened_bound(radius_squared);
  bool complete = true;
  auto leaf = [&](std::uint32_t first, std::uint32_t end) {
    for (std::uint32_t k = first; k < end; ++k) {
      const std::uint32_t i = order_[k];
      if (list.contains(i)) continue;
      const float* p = ordered_xyz_.data() + 3 * static_cast<std::size_t>(k);
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

// The squared distance from q to the box's farthest corner, summed afresh.
double UnlistedTree::farthest_squared(const Box& box, const double* q) noexcept {
  double sum = 0.0;
  for (int d = 0; d < 3; ++d) {
    const double below = q[d] - box.low[d], above = q[d] - box.high[d];
    sum += std::max(below * below, above * above);
  }
  return sum;
}

// Visits the subtrees whose box comes within sqrt(bound) of q: one whose box lies wholly within
// sqrt(inside) goes to `whole`, a leaf otherwise to `leaf`. The box's `nearest` and `farthest`
// are the squared distances from q to its nearest and farthest points, each a sum of per-
// dimension terms of which a split changes one (as in nanoflann's descent). A running sum
// carries the rounding of every level above, which near the root is rounding on the model's
// whole extent, so a subtree is taken whole only when the sum computed afresh agrees.
template <class Leaf, class Whole>
void UnlistedTree::gather(std::uint32_t node, Box& box, const double* q, double bound, double inside, Leaf& leaf,
                          Whole& whole) const noexcept {
  const Node& n = nodes_[node];
  if (box.farthest <= inside && farthest_squared(box, q) <= inside) {
    whole(n.begin, n.end);
    return;
  }
  if (n.feature < 0) {
    leaf(n.first, n.second);
    return;
  }
  const int f = n.feature;
  const double value = q[f];
  const double low = box.low[f], high = box.high[f];
  const double nearest = box.nearest, farthest = box.farthest, near_f = box.near[f], far_f = box.far[f];
  // Child 1 keeps [low, n.low] in dimension f, child 2 [n.high, high].
  const auto visit = [&](double child_low, double child_high, std::uint32_t child) {
    const double below = value - child_low, above = value - child_high;
    const double gap = below < 0.0 ? below : (above > 0.0 ? above : 0.0);
    const double near = gap * gap, far = std::max(below * below, above * above);
    box.nearest = nearest - near_f + near;
    if (!(box.nearest <= bound)) return;  // a NaN query finds nothing
    box.farthest = farthest - far_f + far;
    box.low[f] = child_low;
    box.high[f] = child_high;
    box.near[f] = near;
    box.far[f] = far;
    gather(child, box, q, bound, inside, leaf, whole);
  };
  visit(low, static_cast<double>(n.low), n.first);
  visit(static_cast<double>(n.high), high, n.second);
  box.low[f] = low;
  box.high[f] = high;
  box.near[f] = near_f;
  box.far[f] = far_f;
  box.nearest = nearest;
  box.farthest = farthest;
}

bool UnlistedTree::within_radius_drifted(const PointModel& model, const double* q, double radius, double drift,
                                         std::vector<std::uint32_t>& out) const noexcept {
  if (nodes_.empty()) return true;
  const double radius_squared = radius * radius;
  const double reach = radius + drift;
  const double bound = widened_bound(reach * reach);
  // Narrowed by as much as the bound is widened, against the double rounding of the box's
  // distances; no subtree is taken whole when the drift covers the radius.
  const double core = radius - drift;
  const double inside = core > 0.0 ? core * core * (1.0 - 1e-9) : -1.0;
  bool complete = true;
  auto append = [&](std::uint32_t i) {
    if (out.size() < out.capacity()) {
      out.push_back(i);
    } else {
      complete = false;
    }
  };
  // A point within the core at its snapshot position is within the radius wherever it moved,
  // as a whole subtree is: only the others are read at their current positions, scattered
  // through the model's arrays (a region's ball holds mostly core points).
  auto leaf = [&](std::uint32_t first, std::uint32_t end) {
    for (std::uint32_t k = first; k < end; ++k) {
      const float* p = ordered_xyz_.data() + 3 * static_cast<std::size_t>(k);
      const double snapshot_squared = squared_distance_to(p[0], p[1], p[2], q);
      if (snapshot_squared > bound) continue;
      const std::uint32_t i = order_[k];
      if (snapshot_squared <= inside || current_squared_distance(model, i, q) <= radius_squared) append(i);
    }
  };
  auto whole = [&](std::uint32_t begin, std::uint32_t end) {
    const std::size_t room = out.capacity() - out.size();
    const std::size_t count = end - begin;
    out.insert(out.end(), order_ + begin, order_ + begin + std::min(count, room));
    if (count > room) complete = false;
  };
  Box box;
  box.nearest = box.farthest = 0.0;
  for (int d = 0; d < 3; ++d) {
    box.low[d] = low_[d];
    box.high[d] = high_[d];
    const double below = q[d] - low_[d], above = q[d] - high_[d];
    const double gap = below < 0.0 ? below : (above > 0.0 ? above : 0.0);
    box.near[d] = gap * gap;
    box.far[d] = std::max(below * below, above * above);
    box.nearest += box.near[d];
    box.farthest += box.far[d];
  }
  if (!(box.nearest <= bound)) return true;
  gather(0, box, q, bound, inside, leaf, whole);
  return complete;
}

}  // namespace sculpt::deform
