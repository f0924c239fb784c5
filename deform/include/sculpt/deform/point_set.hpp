#pragma once
// A set of a model's point indices, filled in any order and listed in ascending order: a bit per
// point, and a bit per 64 of those saying which words hold any, so that listing the set costs
// what it holds plus one word per 4,096 points of the model.
//
// Why: a region is the union of a few k-d tree queries, which return their points in the tree's
// spatial order, and the frame wants them ascending (the model's arrays are read in order, and the
// band's least squares must not depend on the tree's shape). A radix sort of a region's few
// thousand indices was 8 % of a 100k-point region frame; setting bits and listing them does
// the same work in one scattered write and one ordered read per point, and drops duplicates
// (overlapping balls) for nothing.

#include <bit>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace sculpt::deform {

class PointSet {
 public:
  PointSet() = default;
  /// Room for indices 0 .. size - 1, empty. Allocates (size / 8 bytes and a little).
  explicit PointSet(std::size_t size) : words_((size + 63) / 64, 0), summary_((words_.size() + 63) / 64, 0) {}

  /// Adds i (below the size given at construction; a caller's bug otherwise, not checked here:
  /// the region's indices come from the model's own index). Adding it twice changes nothing.
  void insert(std::uint32_t i) noexcept {
    const std::size_t word = i / 64;
    words_[word] |= std::uint64_t{1} << (i % 64);
    summary_[word / 64] |= std::uint64_t{1} << (word % 64);
  }

  /// Appends the set's indices to `out` in ascending order, within out's capacity (never
  /// grown: returns false when one did not fit), and empties the set.
  bool drain(std::vector<std::uint32_t>& out) noexcept {
    bool complete = true;
    for (std::size_t s = 0; s < summary_.size(); ++s) {
      std::uint64_t held = summary_[s];
      summary_[s] = 0;
      while (held != 0) {
        const std::size_t word = s * 64 + static_cast<std::size_t>(std::countr_zero(held));
        held &= held - 1;
        std::uint64_t bits = words_[word];
        words_[word] = 0;
        while (bits != 0) {
          const auto i = static_cast<std::uint32_t>(word * 64 + static_cast<std::size_t>(std::countr_zero(bits)));
          bits &= bits - 1;
          if (out.size() < out.capacity()) {
            out.push_back(i);
          } else {
            complete = false;
          }
        }
      }
    }
    return complete;
  }

 private:
  std::vector<std::uint64_t> words_;    // bit i % 64 of word i / 64: index i is in the set
  std::vector<std::uint64_t> summary_;  // bit w % 64 of word w / 64: words_[w] is not zero
};

}  // namespace sculpt::deform
