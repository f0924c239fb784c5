#include "row.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace sculpt::tools::report {

const char* kind_name(RowKind kind) {
  switch (kind) {
    case RowKind::kExact: return "exact";
    case RowKind::kPerFrame: return "per-frame";
    case RowKind::kSession: return "session";
    case RowKind::kTimeOnly: return "time-only";
  }
  return "?";
}

Row labelled(std::string name, std::string group, RowKind kind) {
  Row r;
  r.name = std::move(name);
  r.group = std::move(group);
  r.kind = kind;
  return r;
}

void set_times(Row& row, std::vector<double> ns) {
  row.frames = ns.size();
  if (ns.empty()) return;
  std::sort(ns.begin(), ns.end());
  auto rank = [&](double q) {
    const auto k = static_cast<std::size_t>(std::ceil(q * static_cast<double>(ns.size())));
    return ns[std::clamp<std::size_t>(k, 1, ns.size()) - 1] * 1e-6;
  };
  row.median_ms = rank(0.5);
  row.p99_ms = rank(0.99);
}

}  // namespace sculpt::tools::report
