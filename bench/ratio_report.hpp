#pragma once
// Prints, after Google Benchmark's own table, every frame as a ratio to the yardsticks measured
// in the same run on the same number of points (bench/yardstick.hpp), with its memory per
// point: absolute times differ by up to 1.7x between these machines, ratios much less.

#include <benchmark/benchmark.h>

#include <map>
#include <string>
#include <vector>

namespace sculpt::bench {

class RatioReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override;
  void Finalize() override;

 private:
  struct Result {
    double cpu_ms = 0.0;
    double real_ms = 0.0;
    bool wall = false;  // timed by the wall clock (frames: by hand; their CPU time counts untimed work)
    double points = 0.0;
    double bytes_per_point = 0.0;
    bool from_median = false;
  };
  std::map<std::string, Result> results_;
  std::vector<std::string> order_;
};

/// The names the yardsticks are registered under for `points` points.
std::string bare_name(std::size_t points);
std::string stream_name(std::size_t points);

}  // namespace sculpt::bench
