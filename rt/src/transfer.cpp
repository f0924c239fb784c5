#include "sculpt/rt/transfer.hpp"

#include "sculpt/rt/collision_records.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <unordered_set>

#include "sculpt/base/number_text.hpp"

namespace sculpt::rt {
namespace {

using logging::CollisionRecord;
using logging::RegionKind;

deform::Vec3 to_vec(const logging::Vec3d& v) { return {v[0], v[1], v[2]}; }

std::string frame_name(std::int64_t id) { return "frame " + std::to_string(id); }

[[noreturn]] void reject(std::int64_t id, const std::string& why) { throw FrameRejected(id, why); }

deform::Kernel kernel_of(const CollisionRecord& r) {
  deform::Kernel k;
  k.kind =
      r.kernel == logging::KernelKind::kRegularized ? deform::KernelKind::kRegularized : deform::KernelKind::kKelvin;
  k.regularization = r.kernel_eps;
  k.material.shear_modulus = r.shear_modulus;
  k.material.poisson_ratio = r.poisson_ratio;
  return k;
}

bool finite(const logging::Vec3d& v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }

}  // namespace

FrameRejected::FrameRejected(std::int64_t frame_id, const std::string& why)
    : std::invalid_argument("transfer: " + frame_name(frame_id) + ": " + why), frame_id_(frame_id), why_(why) {}

FrameTransfer::FrameTransfer(deform::PointModel& target, const TransferOptions& options)
    : model_(target), options_(options) {
  if (model_.empty()) throw std::invalid_argument("transfer: the target model has no points");
  if (!(options_.rebuild_drift >= 0.0) || !std::isfinite(options_.rebuild_drift)) {
    throw std::invalid_argument("transfer: the rebuild drift must be finite and >= 0");
  }
  rebuild_drift_ =
      options_.rebuild_drift > 0.0 ? options_.rebuild_drift : kDefaultRebuildFraction * model_.bounding_box_diagonal();
  index_.rebuild(model_);
  extent_ = deform::largest_coordinate(model_);
  const std::size_t n = model_.size();
  points_.reserve(n);
  scratch_.reserve(n);
  journal_.reserve(n, model_.has_normals());
  member_.assign(n, 0);
}

void FrameTransfer::apply(std::span<const CollisionRecord> frame) {
  if (frame.empty()) return;
  const std::int64_t id = frame.front().frame_id;
  if (frame.size() > deform::kMaxSources) {
    reject(id, std::to_string(frame.size()) + " events, more than the " + std::to_string(deform::kMaxSources) +
                   " sources one frame can hold");
  }
  // Validate everything first: a rejected frame must leave the model untouched.
  const CollisionRecord& first = frame.front();
  const deform::Kernel kernel = kernel_of(first);
  try {
    kernel.validate();
  } catch (const std::invalid_argument& e) {
    reject(id, e.what());
  }
  std::array<deform::SourceForce, deform::kMaxSources> forces{};
  bool global = false;
  for (std::size_t e = 0; e < frame.size(); ++e) {
    const CollisionRecord& r = frame[e];
    if (r.frame_id != id) {
      reject(id, "event " + std::to_string(e) + " belongs to " + frame_name(r.frame_id));
    }
    // One jointly solved frame has one kernel; events that disagree were not solved together.
    if (r.kernel != first.kernel || r.kernel_eps != first.kernel_eps || r.shear_modulus != first.shear_modulus ||
        r.poisson_ratio != first.poisson_ratio) {
      reject(id, "its events disagree on the kernel or material");
    }
    if (!finite(r.source) || !finite(r.effective_force)) {
      reject(id, "event " + std::to_string(e) + " has a non-finite source or effective force");
    }
    switch (r.region_kind) {
      case RegionKind::kGlobal: global = true; break;
      case RegionKind::kRadius:
        if (!(r.region_radius > 0.0) || !std::isfinite(r.region_radius) || !finite(r.region_centre)) {
          reject(id, "event " + std::to_string(e) + " has a radius region with radius " +
                         base::number_text(r.region_radius));
        }
        break;
      case RegionKind::kIndexSet: reject(id, "an index-set region cannot be transferred (its points are not recorded)");
      default: reject(id, "unknown region kind");
    }
    forces[e] = {to_vec(r.source), to_vec(r.effective_force)};
  }
  if (global) {
    for (const CollisionRecord& r : frame) {
      if (r.region_kind != RegionKind::kGlobal) reject(id, "its events mix global and radius regions");
    }
  }

  // The region, formed like deform::Region::build: the union of the balls around the contacts
  // at the current positions (the index is exact under drift), ascending.
  points_.clear();
  if (!global) {
    for (const CollisionRecord& r : frame) {
      index_.within_radius(model_, to_vec(r.region_centre), r.region_radius, scratch_, drift_);
      for (std::uint32_t i : scratch_) {
        if (!member_[i]) {
          member_[i] = 1;
          points_.push_back(i);
        }
      }
    }
    std::sort(points_.begin(), points_.end());
    for (std::uint32_t i : points_) member_[i] = 0;
  }

  const std::span<const deform::SourceForce> sources(forces.data(), frame.size());
  // A radius region that catches no point moves nothing; an empty index list must not be read
  // as "all points".
  if (global || !points_.empty()) {
    const deform::FieldResult moved =
        deform::apply_displacements(model_, kernel, sources, points_, global, options_.field, true, &journal_);
    if (!moved.finite) {
      // Finite or nothing: a logged force of 1e300 must not turn the model into NaN.
      journal_.restore(model_);
      reject(id, "its forces give non-finite positions or normals; the model is left as before the frame");
    }
    min_jacobian_ = std::min(min_jacobian_, moved.min_jacobian);
    deform::add_stored_move(moved.max_displacement, drift_, extent_);
  }
  ++frames_;
  events_ += frame.size();
  if (drift_ > rebuild_drift_) {
    index_.rebuild(model_);  // offline: allocating here is fine
    drift_ = 0.0;
    ++rebuilds_;
  }
}

TransferStats transfer(deform::PointModel& target, std::span<const CollisionRecord> events,
                       const std::function<void(std::size_t, std::size_t)>& progress, const TransferOptions& options,
                       const RejectedFrameHandler& on_rejected) {
  // Pass 1: the frame boundaries. A frame whose events are split by another frame is named as
  // such before any size is checked, since its pieces would otherwise only show up as size
  // mismatches.
  std::vector<std::size_t> begin;
  std::unordered_set<std::int64_t> seen;
  for (std::size_t i = 0; i < events.size(); ++i) {
    if (i > 0 && events[i].frame_id == events[i - 1].frame_id) continue;
    const std::int64_t id = events[i].frame_id;
    if (!seen.insert(id).second) {
      reject(id, "its events are split by another frame (event " + std::to_string(i) + ")");
    }
    begin.push_back(i);
  }
  begin.push_back(events.size());
  // Pass 2: each frame has as many events as it says.
  for (std::size_t f = 0; f + 1 < begin.size(); ++f) {
    const std::size_t size = begin[f + 1] - begin[f];
    for (std::size_t k = begin[f]; k < begin[f + 1]; ++k) {
      if (events[k].frame_size != size) {
        reject(events[k].frame_id, "frame_size " + std::to_string(events[k].frame_size) + " but " +
                                       std::to_string(size) + " consecutive events");
      }
    }
    if (size > deform::kMaxSources) {
      reject(events[begin[f]].frame_id, std::to_string(size) + " events, more than the " +
                                            std::to_string(deform::kMaxSources) + " sources one frame can hold");
    }
  }

  TransferStats stats;
  if (events.empty()) return stats;
  FrameTransfer transfer(target, options);
  const std::size_t total = begin.size() - 1;
  for (std::size_t f = 0; f < total; ++f) {
    try {
      transfer.apply(events.subspan(begin[f], begin[f + 1] - begin[f]));
      stats.last_frame = events[begin[f]].frame_id;
    } catch (const FrameRejected& e) {
      if (!on_rejected) throw;
      ++stats.rejected;
      if (!on_rejected(e)) {
        stats.stopped = true;
        break;
      }
    }
    if (progress) progress(f + 1, total);
  }
  stats.frames = transfer.frames_applied();
  stats.events = transfer.events_applied();
  return stats;
}

std::size_t append_frame_records(const deform::FrameReport& report, const deform::DeformSettings& settings,
                                 std::int64_t frame_id, std::int64_t tick, std::vector<CollisionRecord>& out) {
  if (report.collisions == 0 || !report.solve.ok) return 0;
  if (settings.region.kind == deform::RegionSettings::Kind::kIndices) {
    throw std::invalid_argument("transfer: an index-set region cannot be recorded for transfer");
  }
  FrameRecord frame;
  frame.tick = static_cast<std::uint64_t>(tick);
  frame.frame_id = frame_id;
  frame.report = &report;
  frame.settings = &settings;
  std::array<CollisionRecord, deform::kMaxSources> records;
  const std::size_t added = frame_collision_records(frame, records);
  out.insert(out.end(), records.begin(), records.begin() + static_cast<std::ptrdiff_t>(added));
  return added;
}

}  // namespace sculpt::rt
