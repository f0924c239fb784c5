#include "sculpt/deform/point_index.hpp"

#include <nanoflann.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "moved_overlay.hpp"
#include "unlisted_tree.hpp"

namespace sculpt::deform {
namespace {

// Leaf size: measured flat between 8 and 16 for nearest and small-radius queries; 12 keeps the
// tree shallow without scanning long leaves.
constexpr std::size_t kLeafSize = 12;

// The tree searches in double (ElementType double over float storage); every bound is widened by
// widened_bound (unlisted_tree.hpp), shared with the subtree-skipping search.

// Squared snapshot-distance bound for candidates that can be within `radius` now, given that no
// point moved more than `drift`: |q - current| <= r implies |q - snapshot| <= r + drift.
double search_bound(double radius, double drift) {
  const double r = radius + drift;
  return widened_bound(r * r);
}

// The snapshot, interleaved xyz so a leaf scan touches one cache line per few points.
struct Snapshot {
  std::vector<float> xyz;
  std::array<double, 3> low{}, high{};

  std::size_t kdtree_get_point_count() const { return xyz.size() / 3; }
  double kdtree_get_pt(std::uint32_t i, std::size_t dim) const {
    return static_cast<double>(xyz[3 * static_cast<std::size_t>(i) + dim]);
  }
  // The bounding box is gathered while copying, which saves nanoflann a pass.
  template <class Box>
  bool kdtree_get_bbox(Box& box) const {
    for (std::size_t d = 0; d < 3; ++d) {
      box[d].low = low[d];
      box[d].high = high[d];
    }
    return true;
  }
};

using Metric = nanoflann::L2_Simple_Adaptor<double, Snapshot, double, std::uint32_t>;
using Tree = nanoflann::KDTreeSingleIndexAdaptor<Metric, Snapshot, 3, std::uint32_t>;

// nanoflann result set for nearest() without the moved list: tests each candidate at its
// current position and shrinks the snapshot bound to (best current distance + drift) as better
// points turn up.
class NearestCollector {
 public:
  NearestCollector(const PointModel& model, const double* q, double drift) : model_(model), q_(q), drift_(drift) {}
  // The hint is tested like any candidate, so the search starts bounded by its distance.
  void seed(std::uint32_t hint) { addPoint(0.0, hint); }

  std::size_t size() const { return best_index_ == PointIndex::kNoPoint ? 0 : 1; }
  bool full() const { return true; }
  double worstDist() const { return bound_; }  // NOLINT(readability-identifier-naming): nanoflann calls it
  bool addPoint(double /*snapshot_squared_distance*/, std::uint32_t i) {  // NOLINT(readability-identifier-naming)
    const double d2 = current_squared_distance(model_, i, q_);
    if (d2 < best_squared_ || (d2 == best_squared_ && i < best_index_)) {
      best_squared_ = d2;
      best_index_ = i;
      bound_ = drift_ > 0.0 ? search_bound(std::sqrt(d2), drift_) : widened_bound(d2);
    }
    return true;
  }

  std::uint32_t best_index() const { return best_index_; }
  double best_squared() const { return best_squared_; }

 private:
  const PointModel& model_;
  const double* q_;
  double drift_;
  double best_squared_ = std::numeric_limits<double>::infinity();
  std::uint32_t best_index_ = PointIndex::kNoPoint;
  double bound_ = std::numeric_limits<double>::infinity();
};

}  // namespace

double largest_coordinate(const PointModel& model) noexcept {
  // Kept per lane and reduced once: a running scalar maximum does not vectorise, and undoing
  // to the base (Deformer::restore) calls this over every point.
  constexpr std::size_t kLanes = 16;
  std::array<float, kLanes> lanes{};
  for (const std::vector<float>* axis : {&model.x, &model.y, &model.z}) {
    const std::size_t n = axis->size(), whole = n - n % kLanes;
    const float* v = axis->data();
    for (std::size_t k = 0; k < whole; k += kLanes) {
      for (std::size_t l = 0; l < kLanes; ++l) {
        const float a = std::fabs(v[k + l]);
        lanes[l] = a > lanes[l] ? a : lanes[l];
      }
    }
    for (std::size_t k = whole; k < n; ++k) lanes[0] = std::max(lanes[0], std::fabs(v[k]));
  }
  return static_cast<double>(*std::max_element(lanes.begin(), lanes.end()));
}

struct PointIndex::Impl {
  Snapshot points;
  // Built lazily by buildIndex(); holds a reference to `points`, so Impl never moves (it lives
  // behind a unique_ptr).
  Tree tree{3, points,
            nanoflann::KDTreeSingleIndexAdaptorParams(kLeafSize,
                                                      nanoflann::KDTreeSingleIndexAdaptorFlags::SkipInitialBuildIndex)};
  // The tree's shape with its unlisted counts, searched while the moved list is in use.
  UnlistedTree unlisted;
};

PointIndex::PointIndex() = default;
PointIndex::PointIndex(const PointModel& model) { rebuild(model); }
PointIndex::~PointIndex() = default;
PointIndex::PointIndex(PointIndex&&) noexcept = default;
PointIndex& PointIndex::operator=(PointIndex&&) noexcept = default;

void PointIndex::rebuild(const PointModel& model) {
  const std::size_t n = model.size();
  if (n >= kNoPoint) {
    throw std::invalid_argument("point index: " + std::to_string(n) + " points exceed the 32-bit index range");
  }
  if (model.y.size() != n || model.z.size() != n) {
    throw std::invalid_argument("point index: coordinate arrays differ in length");
  }
  if (!impl_) impl_ = std::make_unique<Impl>();
  Snapshot& s = impl_->points;
  s.xyz.resize(3 * n);
  s.low.fill(std::numeric_limits<double>::infinity());
  s.high.fill(-std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < n; ++i) {
    const float p[3] = {model.x[i], model.y[i], model.z[i]};
    for (std::size_t d = 0; d < 3; ++d) {
      s.xyz[3 * i + d] = p[d];
      s.low[d] = std::min(s.low[d], static_cast<double>(p[d]));
      s.high[d] = std::max(s.high[d], static_cast<double>(p[d]));
    }
  }
  impl_->tree.buildIndex();
  impl_->unlisted.build(impl_->tree, n, s.xyz.data());
  unlisted_marked_ = 0;
  if (moved_) moved_->clear();
}

void PointIndex::track_moved(std::size_t capacity, double min_drift) {
  moved_ = std::make_unique<MovedOverlay>(size(), capacity);
  moved_min_drift_ = min_drift;
}

void PointIndex::note_moved(const PointModel& model, std::span<const std::uint32_t> points, bool all,
                            double next_drift) noexcept {
  if (!moved_) return;
  if (all) {
    moved_->note_all();
    return;
  }
  // A list the next queries consult is listed at once; otherwise when a query may consult it.
  if (!(next_drift >= moved_min_drift_)) {
    moved_->defer(model, points);
    return;
  }
  moved_->note(model, points);
  settle_moved(model);  // what was set aside before, and the tree's counts for all of it
}

void PointIndex::prepare_queries(const PointModel& model, double drift) noexcept {
  if (moved_ && !moved_->settled() && drift >= moved_min_drift_) settle_moved(model);
}

void PointIndex::settle_moved(const PointModel& model) noexcept {
  moved_->settle(model);
  if (std::atomic_ref<bool>(list_wanted_).load(std::memory_order_relaxed)) mark_listed();
}

void PointIndex::mark_listed() noexcept {
  if (!impl_ || !moved_) return;
  // Newly listed points are appended to the list: those leave the tree's counts. At most
  // kMarksPerCall at a time, so that an index swapped in with a long list (take_moved, in the
  // loop's tick) catches up over a few frames; queries skip point by point meanwhile.
  constexpr std::size_t kMarksPerCall = 8192;
  const std::span<const std::uint32_t> listed = moved_->listed();
  const std::size_t end = std::min(listed.size(), unlisted_marked_ + kMarksPerCall);
  for (std::size_t s = unlisted_marked_; s < end; ++s) impl_->unlisted.mark_listed(listed[s]);
  unlisted_marked_ = end;
}

void PointIndex::forget_moved() noexcept {
  if (moved_) moved_->clear();
  if (impl_) impl_->unlisted.reset();
  unlisted_marked_ = 0;
}

void PointIndex::take_moved(PointIndex& previous, const PointModel& model) noexcept {
  std::swap(moved_, previous.moved_);
  std::swap(moved_min_drift_, previous.moved_min_drift_);
  std::atomic_ref<bool>(list_wanted_)
      .store(std::atomic_ref<bool>(previous.list_wanted_).load(std::memory_order_relaxed), std::memory_order_relaxed);
  if (!moved_ || !indexes(model)) return;
  const std::vector<float>& xyz = impl_->points.xyz;
  moved_->retain(model, [&](std::uint32_t i) {
    const std::size_t k = 3 * static_cast<std::size_t>(i);
    return model.x[i] != xyz[k] || model.y[i] != xyz[k + 1] || model.z[i] != xyz[k + 2];
  });
  impl_->unlisted.reset();
  unlisted_marked_ = 0;
  if (std::atomic_ref<bool>(list_wanted_).load(std::memory_order_relaxed)) mark_listed();
}

std::size_t PointIndex::moved_count() const noexcept { return moved_ ? moved_->size() + moved_->pending_new() : 0; }

std::size_t PointIndex::moved_capacity() const noexcept { return moved_ ? moved_->capacity() : 0; }

bool PointIndex::moved_complete() const noexcept { return moved_ && moved_->complete(); }

const MovedOverlay* PointIndex::usable_moved(double drift) const noexcept {
  // A list with points still to settle is not used: the query widens by the drift instead, so
  // that exactness never depends on prepare_queries() having been called.
  return moved_ && moved_->complete() && moved_->settled() && drift >= moved_min_drift_ ? moved_.get() : nullptr;
}

bool PointIndex::counts_ready() const noexcept {
  // The tree's counts follow the list only once a query has used the list: before, a frame that
  // moves thousands of points would pay for counts nothing reads (10-20 us of a region frame).
  // Until note_moved has brought them up, a query skips listed points one by one, not by subtree.
  if (unlisted_marked_ == moved_->size()) return true;
  std::atomic_ref<bool>(list_wanted_).store(true, std::memory_order_relaxed);
  return false;
}

std::size_t PointIndex::size() const { return impl_ ? impl_->points.kdtree_get_point_count() : 0; }

bool PointIndex::indexes(const PointModel& model) const noexcept {
  return impl_ && model.size() == size() && model.y.size() == size() && model.z.size() == size();
}

PointIndex::Nearest PointIndex::nearest(const PointModel& model, const Vec3& q, double drift,
                                        std::uint32_t hint) const noexcept {
  if (size() == 0 || !indexes(model)) return {kNoPoint, std::numeric_limits<double>::infinity()};
  const double query[3] = {q.x, q.y, q.z};
  const bool hinted = hint < size();
  // With the moved points listed, the tree holds the others at their snapshot positions: no
  // widening, and the list answers for the moved ones.
  const MovedOverlay* moved = usable_moved(drift);
  if (moved != nullptr) {
    // The tree first, over the points still at their snapshot positions (skipping the listed
    // ones' subtrees): its best then bounds the list's scan, which skips the blocks beyond it.
    std::uint32_t best = kNoPoint;
    double best_squared = std::numeric_limits<double>::infinity();
    if (hinted) {
      const double d2 = current_squared_distance(model, hint, query);
      if (d2 < best_squared) {  // false for a non-finite query, which then finds nothing
        best = hint;
        best_squared = d2;
      }
    }
    impl_->unlisted.nearest(query, *moved, counts_ready(), best, best_squared);
    moved->nearest(model, query, best, best_squared);
    if (best == kNoPoint) return {kNoPoint, std::numeric_limits<double>::infinity()};
    return {best, std::sqrt(best_squared)};
  }
  NearestCollector collector(model, query, std::max(drift, 0.0));
  if (hinted) collector.seed(hint);
  impl_->tree.findNeighbors(collector, query, nanoflann::SearchParams());
  if (collector.best_index() == kNoPoint) {
    // Only reachable with a non-finite query: every comparison failed.
    return {kNoPoint, std::numeric_limits<double>::infinity()};
  }
  return {collector.best_index(), std::sqrt(collector.best_squared())};
}

bool PointIndex::within_radius(const PointModel& model, const Vec3& q, double radius, std::vector<std::uint32_t>& out,
                               double drift, bool ascending) const noexcept {
  out.clear();
  if (!indexes(model) && !(size() == 0 && model.empty())) return false;
  if (size() == 0 || !(radius >= 0.0)) return true;
  const double query[3] = {q.x, q.y, q.z};
  const MovedOverlay* moved = usable_moved(drift);
  bool complete = true;
  if (moved != nullptr) {
    complete = impl_->unlisted.within_radius(query, radius * radius, *moved, counts_ready(), out);
    complete = moved->within_radius(model, query, radius * radius, out) && complete;
  } else {
    complete = impl_->unlisted.within_radius_drifted(model, query, radius, std::max(drift, 0.0), out);
  }
  // Tree order is spatial; callers want index order (stable, cache-friendly writes). std::sort
  // works in place, so this stays allocation-free.
  if (ascending) std::sort(out.begin(), out.end());
  return complete;
}

void PointIndex::k_nearest(const Vec3& q, std::size_t k, std::vector<std::uint32_t>& indices,
                           std::vector<double>& squared_distances) const {
  const std::size_t count = std::min(k, size());
  indices.resize(count);
  squared_distances.resize(count);
  // KNNResultSet reads its last slot as the running bound, so it needs capacity >= 1.
  if (count == 0) return;
  const double query[3] = {q.x, q.y, q.z};
  nanoflann::KNNResultSet<double, std::uint32_t, std::size_t> result(count);
  result.init(indices.data(), squared_distances.data());
  impl_->tree.findNeighbors(result, query, nanoflann::SearchParams());
  indices.resize(result.size());
  squared_distances.resize(result.size());
}

}  // namespace sculpt::deform
