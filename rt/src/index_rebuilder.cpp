#include "sculpt/rt/index_rebuilder.hpp"

#include <algorithm>

namespace sculpt::rt {

IndexRebuilder::IndexRebuilder(std::size_t points, std::size_t points_per_tick)
    : points_per_tick_(std::max<std::size_t>(points_per_tick, 1)) {
  snapshot_.resize(points, false, false);
  worker_ = std::thread([this] { work(); });
}

IndexRebuilder::~IndexRebuilder() {
  state_.store(kQuit);
  state_.notify_one();
  worker_.join();
}

bool IndexRebuilder::request(const deform::PointModel& model, double drift) noexcept {
  if (copying_ || state_.load(std::memory_order_acquire) != kIdle || model.size() != snapshot_.size()) return false;
  drift_at_snapshot_ = drift;
  copied_ = 0;
  copying_ = true;
  copy_chunk(model);
  return true;
}

void IndexRebuilder::advance(const deform::PointModel& model) noexcept {
  if (copying_ && model.size() == snapshot_.size()) copy_chunk(model);
}

void IndexRebuilder::copy_chunk(const deform::PointModel& model) noexcept {
  const std::size_t begin = copied_;
  const std::size_t end = std::min(snapshot_.size(), begin + points_per_tick_);
  const auto from = static_cast<std::ptrdiff_t>(begin), to = static_cast<std::ptrdiff_t>(end);
  std::copy(model.x.begin() + from, model.x.begin() + to, snapshot_.x.begin() + from);
  std::copy(model.y.begin() + from, model.y.begin() + to, snapshot_.y.begin() + from);
  std::copy(model.z.begin() + from, model.z.begin() + to, snapshot_.z.begin() + from);
  copied_ = end;
  if (copied_ < snapshot_.size()) return;
  copying_ = false;
  state_.store(kRequested, std::memory_order_release);
  state_.notify_one();
}

bool IndexRebuilder::install(deform::Deformer& deformer) noexcept {
  if (state_.load(std::memory_order_acquire) != kReady) return false;
  deformer.adopt_index(fresh_, drift_at_snapshot_);
  ++installed_;
  state_.store(kRetire, std::memory_order_release);  // fresh_ now holds the old tree
  state_.notify_one();
  return true;
}

void IndexRebuilder::work() {
  // Every transition the worker makes is a compare-and-swap, so a kQuit stored by the
  // destructor at any moment is never overwritten (it was, and the join hung).
  for (;;) {
    state_.wait(kIdle);
    int s = state_.load(std::memory_order_acquire);
    if (s == kQuit) return;
    if (s == kRequested) {
      fresh_.rebuild(snapshot_);  // allocates: that is why it happens here
      int expected = kRequested;
      if (!state_.compare_exchange_strong(expected, kReady, std::memory_order_acq_rel)) return;  // quit
      state_.wait(kReady);
      s = state_.load(std::memory_order_acquire);
      if (s == kQuit) return;
    }
    if (s == kRetire) {
      fresh_ = deform::PointIndex();
      int expected = kRetire;
      if (!state_.compare_exchange_strong(expected, kIdle, std::memory_order_acq_rel)) return;  // quit
    }
  }
}
}  // namespace sculpt::rt
