#include "pareto.hpp"

namespace sculpt::tools::report {

bool plotted(const Row& row) {
  return (row.kind == RowKind::kPerFrame || row.kind == RowKind::kSession) && row.frames > 0 && row.median_ms > 0.0 &&
         row.mean_error > 0.0;
}

void mark_pareto_front(std::vector<Row>& rows) {
  for (Row& r : rows) {
    r.pareto = plotted(r);
    for (const Row& o : rows) {
      if (!r.pareto) break;
      if (&o == &r || !plotted(o)) continue;
      const bool no_worse = o.median_ms <= r.median_ms && o.mean_error <= r.mean_error;
      const bool better = o.median_ms < r.median_ms || o.mean_error < r.mean_error;
      if (no_worse && better) r.pareto = false;
    }
  }
}

}  // namespace sculpt::tools::report
