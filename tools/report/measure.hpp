#pragma once
// Measuring the rows: the per-frame rows on the exact trajectory of a recorded session, and the
// session rows of the reduced model set against the exact session's end.

#include <functional>
#include <string>
#include <vector>

#include "exact_state.hpp"
#include "row.hpp"
#include "session_capture.hpp"

namespace sculpt::tools::report {

/// Called as work advances: what is being measured, and how far along it is.
using Progress = std::function<void(const std::string& what, std::size_t done, std::size_t total)>;

/// The exact session and the per-frame rows: every recorded step is computed exactly from the
/// exact state, and once with each approximation started from a float copy of that same state.
/// Returns the exact row first, then the approximations, then the time-only row; `exact_end`
/// receives the exact session's end state.
std::vector<Row> per_frame_rows(const RecordedSession& session, ExactState& exact_end, const Progress& progress);

/// The reduced model set (thesis 4.4.1): the scene recorded on `ratios` of the full model and
/// transferred to it (rt::transfer), compared with `exact_end` at the session's end; and the
/// full session in float as its scene asks (`full`), and the whole session with a region of 10 and 20 spacings and
/// with the normals left as they were, the same way. `samples` are the logged session's glove
/// samples, or null for the scene's scripted ones. Times are the recording's frame times.
std::vector<Row> session_rows(const rt::Scene& scene, const rt::SampleLog* samples, const RecordedSession& full,
                              const ExactState& exact_end, const std::vector<double>& ratios, const Progress& progress);

}  // namespace sculpt::tools::report
