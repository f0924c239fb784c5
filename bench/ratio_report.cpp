#include "ratio_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace sculpt::bench {

std::string bare_name(std::size_t points) { return "Bare5/" + std::to_string(points); }
std::string stream_name(std::size_t points) { return "Stream/" + std::to_string(points); }

namespace {

double to_ms(double t, benchmark::TimeUnit unit) {
  switch (unit) {
    case benchmark::kNanosecond: return t * 1e-6;
    case benchmark::kMicrosecond: return t * 1e-3;
    case benchmark::kMillisecond: return t;
    case benchmark::kSecond: return t * 1e3;
  }
  return t;
}

double counter(const benchmark::BenchmarkReporter::Run& run, const char* name) {
  const auto it = run.counters.find(name);
  return it == run.counters.end() ? 0.0 : it->second.value;
}

}  // namespace

void RatioReporter::ReportRuns(const std::vector<Run>& runs) {
  ConsoleReporter::ReportRuns(runs);
  for (const Run& run : runs) {
    if (run.error_occurred) continue;
    // With --benchmark_repetitions the median aggregate speaks for the name; without, the run.
    const bool median = run.run_type == Run::RT_Aggregate && run.aggregate_name == "median";
    if (run.run_type == Run::RT_Aggregate && !median) continue;
    const std::string name = run.run_name.str();
    auto [it, fresh] = results_.try_emplace(name);
    if (fresh) order_.push_back(name);
    if (it->second.from_median && !median) continue;
    Result& r = it->second;
    r.cpu_ms = to_ms(run.GetAdjustedCPUTime(), run.time_unit);
    r.real_ms = to_ms(run.GetAdjustedRealTime(), run.time_unit);
    r.wall = !run.run_name.time_type.empty();  // "manual_time" or "real_time"
    r.points = counter(run, "points");
    r.bytes_per_point = counter(run, "bytes/point");
    r.from_median = median;
  }
}

void RatioReporter::Finalize() {
  ConsoleReporter::Finalize();
  std::printf(
      "\nRatios in this run (a frame's wall time, the deformer's call alone, over the yardstick's; T =\n"
      "the bare five-source Kelvin pass on one core on as many points, S = one streaming pass over\n"
      "the positions; T(100k) = the same pass on 100,250 points, the issue's yardstick for every\n"
      "model size):\n");
  int width = 52;  // the longest frame name, so that the columns stay aligned
  for (const std::string& name : order_) width = std::max(width, static_cast<int>(name.size()));
  std::printf("%-*s %10s %9s %10s %9s %12s\n", width, "frame", "ms", "x T", "x T(100k)", "x S", "bytes/point");
  const auto bare_100k = results_.find(bare_name(100250));
  bool missing = false;
  for (const std::string& name : order_) {
    const Result& r = results_.at(name);
    if (!(r.points > 0.0)) continue;  // a yardstick itself
    const auto n = static_cast<std::size_t>(std::llround(r.points));
    const auto bare = results_.find(bare_name(n)), stream = results_.find(stream_name(n));
    const double ms = r.wall ? r.real_ms : r.cpu_ms;
    // A yardstick the filter left out leaves its column empty ("-"), said below the table.
    auto ratio = [&](const auto& it, int width, int decimals) {
      char cell[32];
      if (it == results_.end()) {
        missing = true;
        std::snprintf(cell, sizeof cell, "%*s", width, "-");
      } else {
        std::snprintf(cell, sizeof cell, "%*.*f", width, decimals,
                      ms / (r.wall ? it->second.real_ms : it->second.cpu_ms));
      }
      return std::string(cell);
    };
    std::printf("%-*s %10.4f %s %s %s %12.0f\n", width, name.c_str(), ms, ratio(bare, 9, 2).c_str(),
                ratio(bare_100k, 10, 3).c_str(), ratio(stream, 9, 2).c_str(), r.bytes_per_point);
  }
  if (missing) {
    std::printf("(-: its yardstick did not run; add Bare5|Stream to --benchmark_filter for every ratio)\n");
  }
  for (const std::string& name : order_) {
    const Result& r = results_.at(name);
    if (r.points > 0.0) continue;
    std::printf("%-*s %10.4f\n", width, name.c_str(), r.cpu_ms);
  }
}

}  // namespace sculpt::bench
