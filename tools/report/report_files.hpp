#pragma once
// The report's files: report.csv (every row, every column), report.md (the table and a short
// reading of it) and pareto.png (gnuplot, driven from the CSV).

#include <string>
#include <vector>

#include "row.hpp"

namespace sculpt::tools::report {

/// What the report is about, for the headings.
struct ReportContext {
  std::string session;  ///< the scene or log
  std::string model;    ///< the model's path
  std::size_t points = 0;
  std::size_t steps = 0;
};

/// The CSV's columns, in order (the guard counts after probe_inside, in for_each_guard order).
std::vector<std::string> csv_columns();

void write_csv(const std::string& path, const std::vector<Row>& rows);
void write_markdown(const std::string& path, const std::vector<Row>& rows, const ReportContext& context,
                    const std::string& plot_note);

/// Writes `dir`/pareto.gp and pareto_front.dat (the front of `rows`, by time) and runs gnuplot on
/// `dir`/report.csv. Returns an empty string when
/// pareto.png was written, otherwise why not (gnuplot missing, or it failed), for the user.
std::string plot_pareto(const std::string& dir, const std::vector<Row>& rows, const ReportContext& context);

}  // namespace sculpt::tools::report
