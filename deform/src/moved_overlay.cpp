#include "moved_overlay.hpp"

#include <algorithm>
#include <limits>

namespace sculpt::deform {

MovedOverlay::MovedOverlay(std::size_t model_size, std::size_t capacity)
    : slot_(model_size, 0),
      listed_((model_size + 63) / 64, 0),
      ids_(std::min(capacity, model_size)),
      boxes_((ids_.size() + kBlock - 1) / kBlock),
      groups_((boxes_.size() + kGroup - 1) / kGroup),
      pending_(ids_.size()),
      pending_bits_(listed_.size(), 0) {
  reset_boxes();
}

void MovedOverlay::defer(const PointModel& model, std::span<const std::uint32_t> points) noexcept {
  if (pending_.empty()) {  // a list without room: note() marks it overflowed
    note(model, points);
    return;
  }
  for (const std::uint32_t i : points) {
    std::uint64_t& word = pending_bits_[i / 64];
    const std::uint64_t bit = std::uint64_t{1} << (i % 64);
    if (word & bit) continue;
    if (pending_count_ == pending_.size()) settle(model);  // full: list what is waiting
    word |= bit;
    pending_[pending_count_++] = i;
    if (!contains(i)) ++pending_new_;
  }
}

void MovedOverlay::settle(const PointModel& model) noexcept {
  if (pending_count_ == 0) return;
  const std::span<const std::uint32_t> points(pending_.data(), pending_count_);
  note(model, points);
  for (const std::uint32_t i : points) pending_bits_[i / 64] &= ~(std::uint64_t{1} << (i % 64));
  pending_count_ = 0;
  pending_new_ = 0;
}

void MovedOverlay::reset_boxes() noexcept {
  constexpr float kInf = std::numeric_limits<float>::infinity();
  for (Box& b : boxes_) b = Box{{kInf, kInf, kInf}, {-kInf, -kInf, -kInf}};
  for (Box& b : groups_) b = Box{{kInf, kInf, kInf}, {-kInf, -kInf, -kInf}};
}

std::size_t MovedOverlay::list(std::uint32_t i) noexcept {
  // The bit first: the bits of 100,000 points fit in the cache, their slots do not, and a new
  // point's slot is only written (a store does not hold a loop up as a load does).
  if (contains(i)) return slot_[i];
  if (count_ == ids_.size()) {
    overflowed_ = true;
    return 0;
  }
  ids_[count_] = i;
  slot_[i] = static_cast<std::uint32_t>(++count_);
  listed_[i / 64] |= std::uint64_t{1} << (i % 64);
  return count_;
}

void MovedOverlay::note(const PointModel& model, std::span<const std::uint32_t> points) noexcept {
  // Each listed point grows its block's box. The box being grown is held in registers until the
  // slots move on to the next block: growing it in memory point by point made each minimum wait
  // on the store before it, and that chain was most of the time (a region frame notes thousands
  // of points, new ones in consecutive slots).
  constexpr float kInf = std::numeric_limits<float>::infinity();
  constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();
  std::size_t open = kNone;
  float low[3] = {kInf, kInf, kInf}, high[3] = {-kInf, -kInf, -kInf};
  auto flush = [&] {
    if (open == kNone) return;
    Box& b = boxes_[open];
    Box& g = groups_[open / kGroup];
    for (int d = 0; d < 3; ++d) {
      b.low[d] = std::min(b.low[d], low[d]);
      b.high[d] = std::max(b.high[d], high[d]);
      g.low[d] = std::min(g.low[d], low[d]);
      g.high[d] = std::max(g.high[d], high[d]);
    }
  };
  for (std::uint32_t i : points) {
    const std::size_t s = list(i);
    if (s == 0) continue;
    const std::size_t box = (s - 1) / kBlock;
    if (box != open) {
      flush();
      open = box;
      for (int d = 0; d < 3; ++d) {
        low[d] = kInf;
        high[d] = -kInf;
      }
    }
    const float p[3] = {model.x[i], model.y[i], model.z[i]};
    for (int d = 0; d < 3; ++d) {
      low[d] = std::min(low[d], p[d]);
      high[d] = std::max(high[d], p[d]);
    }
  }
  flush();
}

void MovedOverlay::clear() noexcept {
  for (std::size_t s = 0; s < count_; ++s) {
    const std::uint32_t i = ids_[s];
    slot_[i] = 0;
    listed_[i / 64] &= ~(std::uint64_t{1} << (i % 64));
  }
  count_ = 0;
  overflowed_ = false;
  reset_boxes();
  for (std::size_t k = 0; k < pending_count_; ++k) {
    const std::uint32_t i = pending_[k];
    pending_bits_[i / 64] &= ~(std::uint64_t{1} << (i % 64));
  }
  pending_count_ = 0;
  pending_new_ = 0;
}

double MovedOverlay::box_squared_distance(const Box& b, const double* q) noexcept {
  // Rounding is monotone, so for a point inside the box each gap computed here is at most that
  // point's |x - q| computed by current_squared_distance, and so is the sum of their squares:
  // a block is skipped only when none of its points can tie the bound.
  double sum = 0.0;
  for (int d = 0; d < 3; ++d) {
    const double low = b.low[d], high = b.high[d];
    double gap = 0.0;
    if (q[d] < low) {
      gap = low - q[d];
    } else if (q[d] > high) {
      gap = q[d] - high;
    }
    sum += gap * gap;
  }
  return sum;
}

void MovedOverlay::nearest(const PointModel& model, const double* q, std::uint32_t& best,
                           double& best_squared) const noexcept {
  for_each_block_near(q, best_squared, [&](std::size_t first, std::size_t last) {
    for (std::size_t s = first; s < last; ++s) {
      const std::uint32_t i = ids_[s];
      const double d2 = current_squared_distance(model, i, q);
      if (d2 < best_squared || (d2 == best_squared && i < best)) {
        best_squared = d2;
        best = i;
      }
    }
  });
}

bool MovedOverlay::within_radius(const PointModel& model, const double* q, double radius_squared,
                                 std::vector<std::uint32_t>& out) const noexcept {
  bool complete = true;
  for_each_block_near(q, radius_squared, [&](std::size_t first, std::size_t last) {
    for (std::size_t s = first; s < last; ++s) {
      const std::uint32_t i = ids_[s];
      if (current_squared_distance(model, i, q) > radius_squared) continue;
      if (out.size() < out.capacity()) {
        out.push_back(i);
      } else {
        complete = false;
      }
    }
  });
  return complete;
}

}  // namespace sculpt::deform
