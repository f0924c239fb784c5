#include "sculpt/deform/ball_cache.hpp"

#include <algorithm>
#include <cmath>
#include <span>

#include "moved_overlay.hpp"

namespace sculpt::deform {

namespace {

// Passes to keep every candidate within the radius of q at its current position, by the tree's
// own comparison; keep may write over the candidate it was just given.
template <typename Keep>
void for_each_within(const PointModel& model, std::span<const std::uint32_t> candidates, const double (&q)[3],
                     double radius_squared, Keep&& keep) noexcept {
  for (const std::uint32_t i : candidates) {
    if (current_squared_distance(model, i, q) <= radius_squared) keep(i);
  }
}

}  // namespace

BallCache::BallCache(std::size_t capacity, double margin, bool ascending) : margin_(margin), ascending_(ascending) {
  pool_.reserve(capacity);
}

void BallCache::add_move(double distance) noexcept {
  if (!std::isfinite(distance)) {
    forget();
    return;
  }
  if (!(distance > 0.0)) return;
  for (std::size_t b = 0; b < ball_count_; ++b) balls_[b].moved += distance;
}

void BallCache::forget() noexcept {
  ball_count_ = 0;
  pool_.clear();
  asked_count_ = asked_next_ = 0;
}

bool BallCache::asked_before_near(const Vec3& c, double reach) const noexcept {
  for (std::size_t k = 0; k < asked_count_; ++k) {
    const Asked& a = asked_[k];
    if (a.frame < frame_ && frame_ - a.frame <= kRecentFrames && norm(c - a.centre) <= reach) return true;
  }
  return false;
}

const BallCache::Ball* BallCache::covering(const Vec3& c, double radius) const noexcept {
  // A point within radius of c now was within radius + |c - centre| + moved of the centre when
  // the ball was found. The relative margin stands far above the rounding of these distances
  // (and of the moves' running sum), so that the candidates hold every point the tree's query
  // would find, whatever the rounding.
  // Of the balls that cover it, the one with the fewest candidates to test.
  constexpr double kSlack = 1.0 + 1e-9;
  const Ball* best = nullptr;
  for (std::size_t b = 0; b < ball_count_; ++b) {
    const Ball& ball = balls_[b];
    if (!((radius + norm(c - ball.centre) + ball.moved) * kSlack <= ball.radius)) continue;
    if (best == nullptr || ball.count < best->count) best = &ball;
  }
  return best;
}

bool BallCache::make_room(std::size_t count) noexcept {
  if (ball_count_ < kMaxBalls && pool_.size() + count <= pool_.capacity()) return true;
  std::size_t kept = 0, end = 0;
  for (std::size_t b = 0; b < ball_count_; ++b) {
    Ball ball = balls_[b];
    if (!ball.used) continue;
    // Moved towards the front (std::copy may not write where it reads from: a ball in place stays).
    if (ball.begin != end) {
      std::copy(pool_.begin() + static_cast<std::ptrdiff_t>(ball.begin),
                pool_.begin() + static_cast<std::ptrdiff_t>(ball.begin + ball.count),
                pool_.begin() + static_cast<std::ptrdiff_t>(end));
    }
    ball.begin = end;
    end += ball.count;
    balls_[kept++] = ball;
  }
  ball_count_ = kept;
  pool_.resize(end);
  return ball_count_ < kMaxBalls && end + count <= pool_.capacity();
}

bool BallCache::within_radius(const PointModel& model, const PointIndex& index, double drift, const Vec3& c,
                              double radius, std::vector<std::uint32_t>& out) noexcept {
  const double q[3] = {c.x, c.y, c.z};
  const double radius_squared = radius * radius;
  const auto ask_index = [&] { return index.within_radius(model, c, radius, out, drift, ascending_); };
  if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z) || !(radius >= 0.0) || !std::isfinite(radius)) {
    return ask_index();  // nothing worth keeping
  }
  asked_[asked_next_] = Asked{c, frame_};
  asked_next_ = (asked_next_ + 1) % asked_.size();
  asked_count_ = std::min(asked_count_ + 1, asked_.size());
  const Ball* ball = covering(c, radius);
  if (ball == nullptr) {
    const double wider = radius * (1.0 + margin_);
    if (!asked_before_near(c, wider - radius)) {
      ++plain_;
      return ask_index();
    }
    ++wider_;
    // Not every candidate fitted, or no room to keep them: the plain query answers exactly.
    if (!index.within_radius(model, c, wider, out, drift, /*ascending=*/false)) return ask_index();
    if (!make_room(out.size())) {
      // No room to keep them: this frame's answer from the candidates alone, in place.
      std::size_t kept = 0;
      for_each_within(model, out, q, radius_squared, [&](std::uint32_t i) { out[kept++] = i; });
      out.resize(kept);
      if (ascending_) std::sort(out.begin(), out.end());
      return true;
    }
    Ball& fresh = balls_[ball_count_++];
    fresh = Ball{c, wider, 0.0, pool_.size(), out.size(), true};
    pool_.insert(pool_.end(), out.begin(), out.end());
    // Kept in the order the queries want, so that every later query comes out in it for free.
    if (ascending_) std::sort(pool_.begin() + static_cast<std::ptrdiff_t>(fresh.begin), pool_.end());
    ball = &fresh;
  } else {
    ++hits_;
  }
  balls_[static_cast<std::size_t>(ball - balls_.data())].used = true;
  out.clear();
  bool complete = true;
  for_each_within(model, {pool_.data() + ball->begin, ball->count}, q, radius_squared, [&](std::uint32_t i) {
    if (out.size() < out.capacity()) {
      out.push_back(i);
    } else {
      complete = false;
    }
  });
  return complete;
}

PointIndex::Nearest BallCache::nearest(const PointModel& model, const PointIndex& index, double drift, const Vec3& q,
                                       std::uint32_t hint) noexcept {
  const auto ask_index = [&] { return index.nearest(model, q, drift, hint); };
  if (hint >= model.size() || !index.indexes(model) || !is_finite(q)) return ask_index();
  const double query[3] = {q.x, q.y, q.z};
  // The nearest point is no farther than the hint: every point that close is in a covering ball.
  const double hint_squared = current_squared_distance(model, hint, query);
  const Ball* ball = covering(q, std::sqrt(hint_squared));
  if (ball == nullptr) return ask_index();
  ++hits_;
  balls_[static_cast<std::size_t>(ball - balls_.data())].used = true;
  std::uint32_t best = hint;
  double best_squared = hint_squared;
  const std::uint32_t* candidates = pool_.data() + ball->begin;
  for (std::size_t k = 0; k < ball->count; ++k) {
    const std::uint32_t i = candidates[k];
    const double d2 = current_squared_distance(model, i, query);
    if (d2 < best_squared || (d2 == best_squared && i < best)) {
      best_squared = d2;
      best = i;
    }
  }
  return {best, std::sqrt(best_squared)};
}

void BallCache::end_frame() noexcept {
  for (std::size_t b = 0; b < ball_count_; ++b) balls_[b].used = false;
  ++frame_;
}

}  // namespace sculpt::deform
