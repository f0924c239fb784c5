#pragma once
// The k-d tree's shape with, for every subtree, whether the tree still answers for any of its
// points (any not on the moved list), so that a query which leaves the moved points to the list
// skips whole subtrees of them.
//
// Why: under a deep dent the snapshot's surface lies between a finger and the points it now
// touches. A query above the dent must rule out every snapshot point nearer than the true
// nearest one, and the dent's moved points are thousands of such points: on a two-million-point
// sphere pressed by five fingers those queries were 70 % of a frame (37 us each, measured), all
// of it spent visiting points the list answers for. Their subtrees hold nothing to find.
//
// The traversal is nanoflann's (the same descent order, the same incremental box distances),
// written here because nanoflann offers no way to prune a subtree by anything but its box.
//
// The same tree answers radius queries without the list too (within_radius_drifted): there it
// takes a subtree that lies wholly inside the ball whole, where nanoflann tests each of its points,
// and it reads the snapshot in the tree's own order, so that a leaf is a few contiguous cache
// lines instead of a dozen scattered ones.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "moved_overlay.hpp"
#include "sculpt/deform/point_model.hpp"

namespace sculpt::deform {

// The tree searches in double over float storage, so pruning decisions carry only double
// rounding error. Each search bound is still widened by this relative amount, plus the smallest
// normal double so that a zero radius admits exact hits. Every candidate is re-tested exactly,
// so the widening costs a few extra tests at most.
inline double widened_bound(double squared_bound) {
  constexpr double kRelativeSlack = 1e-9;
  return squared_bound * (1.0 + kRelativeSlack) + std::numeric_limits<double>::min();
}

class UnlistedTree {
 public:
  /// Copies the shape of a built nanoflann tree over `points` points (its nodes and its bounding
  /// box; its point order is read in place, so the tree must outlive this copy and not be
  /// rebuilt without it) and the snapshot `xyz` (interleaved, model order) in the tree's order;
  /// every point counts as unlisted. Set-up: allocates about 24 bytes a point.
  template <class Tree>
  void build(const Tree& tree, std::size_t points, const float* xyz);
  /// Every point is the tree's again (the list was cleared).
  void reset() noexcept { unlisted_ = initial_; }
  /// Point i is now on the list. Call once per point listed. Touches its leaf alone, except for
  /// the last unlisted point of a leaf, whose emptiness goes up as far as it empties subtrees.
  void mark_listed(std::uint32_t i) noexcept;

  /// Improves (best, best_squared) with the unlisted points at their snapshot positions
  /// (the tree-ordered copy): a point wins when closer, or as close with a smaller index. With
  /// `by_subtree` (the counts are up to the list) subtrees with no unlisted point are skipped
  /// whole; without, listed points are skipped one by one.
  void nearest(const double* q, const MovedOverlay& list, bool by_subtree, std::uint32_t& best,
               double& best_squared) const noexcept;
  /// Appends the unlisted points within sqrt(radius_squared) of q (snapshot positions) to
  /// `out`, within its capacity; false when one did not fit. `by_subtree` as for nearest().
  bool within_radius(const double* q, double radius_squared, const MovedOverlay& list, bool by_subtree,
                     std::vector<std::uint32_t>& out) const noexcept;
  /// Without the list: appends the points of `model` within `radius` of q at their current
  /// positions, given that none moved more than `drift` from its snapshot position, within out's
  /// capacity (false when one did not fit). A point within radius - drift of q at its snapshot
  /// position is appended untested, and so is a subtree whose box lies wholly within that core,
  /// since every such point is within the radius wherever it moved; a point between the core and
  /// radius + drift is tested at its current position. Order: the tree's.
  bool within_radius_drifted(const PointModel& model, const double* q, double radius, double drift,
                             std::vector<std::uint32_t>& out) const noexcept;

 private:
  static constexpr std::uint32_t kNone = 0xFFFFFFFFu;
  struct Node {
    // Split values: nanoflann's divlow (child 1's largest coordinate) rounded up and divhigh
    // (child 2's smallest) rounded down, so that a cut distance is never overestimated. They
    // are float coordinates, so the rounding is exact in practice.
    float low = 0.0f, high = 0.0f;
    std::uint32_t first = 0;    // child 1, or a leaf's first position in order_
    std::uint32_t second = 0;   // child 2, or a leaf's end position in order_
    std::int32_t feature = -1;  // split dimension; -1 for a leaf
    // The subtree's points: positions begin..end of order_ (a subtree's points are contiguous
    // there, nanoflann partitions in place).
    std::uint32_t begin = 0, end = 0;
  };
  // A subtree's bounding box, narrowed split by split on the way down, with each dimension's
  // squared distance from the query to its nearest and farthest side and their sums.
  struct Box {
    double low[3], high[3];
    double near[3], far[3];
    double nearest, farthest;
  };
  template <class NodePtr>
  static std::size_t count_nodes(NodePtr node);
  template <class NodePtr>
  std::uint32_t flatten(NodePtr node, std::uint32_t parent);
  template <bool kBySubtree, class Leaf>
  void descend(std::uint32_t node, double min_distance, double* distances, const double* q, const double& bound,
               Leaf& leaf) const noexcept;
  template <class Leaf>
  void search(const double* q, const double& bound, bool by_subtree, Leaf& leaf) const noexcept;
  static double farthest_squared(const Box& box, const double* q) noexcept;
  template <class Leaf, class Whole>
  void gather(std::uint32_t node, Box& box, const double* q, double bound, double inside, Leaf& leaf,
              Whole& whole) const noexcept;

  std::vector<Node> nodes_;
  // unlisted_: for a leaf, how many of its points are not listed; for an inner node, how many
  // of its two children still hold such a point. Zero means nothing to find below. initial_
  // holds the counts with nothing listed.
  std::vector<std::uint32_t> parent_, initial_, unlisted_;
  const std::uint32_t* order_ = nullptr;  // point indices in tree order (nanoflann's vAcc)
  std::vector<float> ordered_xyz_;        // the snapshot in tree order: position k is point order_[k]
  std::vector<std::uint32_t> leaf_of_;    // per point: its leaf
  double low_[3] = {}, high_[3] = {};     // the root's bounding box
};

template <class Tree>
void UnlistedTree::build(const Tree& tree, std::size_t points, const float* xyz) {
  nodes_.clear();
  parent_.clear();
  initial_.clear();
  order_ = tree.vAcc.data();
  ordered_xyz_.resize(3 * points);
  for (std::size_t k = 0; k < points; ++k) {
    for (std::size_t d = 0; d < 3; ++d) ordered_xyz_[3 * k + d] = xyz[3 * static_cast<std::size_t>(order_[k]) + d];
  }
  leaf_of_.assign(points, kNone);
  const std::size_t count = tree.root_node != nullptr ? count_nodes(tree.root_node) : 0;
  nodes_.reserve(count);
  parent_.reserve(count);
  initial_.reserve(count);
  for (int d = 0; d < 3; ++d) {
    low_[d] = static_cast<double>(tree.root_bbox[d].low);
    high_[d] = static_cast<double>(tree.root_bbox[d].high);
  }
  if (tree.root_node != nullptr) flatten(tree.root_node, kNone);
  unlisted_ = initial_;
}

template <class NodePtr>
std::size_t UnlistedTree::count_nodes(NodePtr node) {
  return node->child1 == nullptr ? 1 : 1 + count_nodes(node->child1) + count_nodes(node->child2);
}

template <class NodePtr>
std::uint32_t UnlistedTree::flatten(NodePtr node, std::uint32_t parent) {
  const auto id = static_cast<std::uint32_t>(nodes_.size());
  nodes_.emplace_back();
  parent_.push_back(parent);
  initial_.push_back(2);
  if (node->child1 == nullptr) {  // nanoflann's mark of a leaf
    const auto left = static_cast<std::uint32_t>(node->node_type.lr.left);
    const auto right = static_cast<std::uint32_t>(node->node_type.lr.right);
    nodes_[id].first = left;
    nodes_[id].second = right;
    nodes_[id].begin = left;
    nodes_[id].end = right;
    for (std::uint32_t k = left; k < right; ++k) leaf_of_[order_[k]] = id;
    initial_[id] = right - left;
    return id;
  }
  const std::uint32_t first = flatten(node->child1, id);
  const std::uint32_t second = flatten(node->child2, id);
  Node& n = nodes_[id];
  n.feature = static_cast<std::int32_t>(node->node_type.sub.divfeat);
  const auto low = static_cast<double>(node->node_type.sub.divlow);
  const auto high = static_cast<double>(node->node_type.sub.divhigh);
  n.low = static_cast<float>(low);
  n.high = static_cast<float>(high);
  if (static_cast<double>(n.low) < low) n.low = std::nextafter(n.low, std::numeric_limits<float>::infinity());
  if (static_cast<double>(n.high) > high) n.high = std::nextafter(n.high, -std::numeric_limits<float>::infinity());
  n.first = first;
  n.second = second;
  n.begin = nodes_[first].begin;
  n.end = nodes_[second].end;
  return id;
}

}  // namespace sculpt::deform
