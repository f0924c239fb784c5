#include "sculpt/rt/index_rebuilder.hpp"

#include <algorithm>

namespace sculpt::rt {

IndexRebuilder::IndexRebuilder(std::size_t points) {
  snapshot_.resize(points, false, false);
  worker_ = std::thread([this] { work(); });
}

IndexRebuilder::~IndexRebuilder() {
  state_.store(kQuit);
  state_.notify_one();
  worker_.join();
}

bool IndexRebuilder::request(const deform::PointModel& model, double drift) noexcept {
  if (state_.load(std::memory_order_acquire) != kIdle || model.size() != snapshot_.size()) return false;
  std::copy(model.x.begin(), model.x.end(), snapshot_.x.begin());
  std::copy(model.y.begin(), model.y.end(), snapshot_.y.begin());
  std::copy(model.z.begin(), model.z.end(), snapshot_.z.begin());
  drift_at_snapshot_ = drift;
  state_.store(kRequested, std::memory_order_release);
  state_.notify_one();
  return true;
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
