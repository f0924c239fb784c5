#pragma once
// The Pareto front of error against time: the rows no other row beats on both.

#include <vector>

#include "row.hpp"

namespace sculpt::tools::report {

/// True for rows that stand on the plot: measured rows with a time and an error (the exact
/// row's error is zero by definition and a time-only row has none).
bool plotted(const Row& row);

/// Sets Row::pareto: a plotted row is on the front when no other plotted row is at least as
/// fast and at least as accurate (median time, mean error) and better in one of them.
void mark_pareto_front(std::vector<Row>& rows);

}  // namespace sculpt::tools::report
