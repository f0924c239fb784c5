#pragma once
// "did you mean": the nearest known word to a mistyped one, by edit distance.

#include <span>
#include <string>

namespace sculpt::tools {

/// Levenshtein distance: the fewest single-character insertions, deletions and substitutions
/// that turn `a` into `b`.
std::size_t edit_distance(const std::string& a, const std::string& b);

/// The candidate nearest to `word`, or empty when even the nearest is so far that suggesting it
/// would mislead (more than a third of the word's length, and at least two, edits away).
std::string did_you_mean(const std::string& word, std::span<const std::string> candidates);

}  // namespace sculpt::tools
