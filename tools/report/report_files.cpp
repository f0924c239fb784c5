#include "report_files.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <stdexcept>

#include "pareto.hpp"
#include "sculpt/deform/deformer.hpp"

namespace sculpt::tools::report {
namespace {

std::ofstream open(const std::string& path) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error("cannot write " + path);
  return out;
}

std::string g(double v, const char* format = "%.4g") {
  char text[64];
  std::snprintf(text, sizeof text, format, v);
  return text;
}

std::string percent(double fraction) { return g(fraction * 100.0, "%.3g") + " %"; }

const Row* find(const std::vector<Row>& rows, const std::string& name) {
  for (const Row& r : rows) {
    if (r.name == name) return &r;
  }
  return nullptr;
}

// Column numbers gnuplot needs (1-based).
int column(const std::string& name) {
  const std::vector<std::string> c = csv_columns();
  for (std::size_t k = 0; k < c.size(); ++k) {
    if (c[k] == name) return static_cast<int>(k) + 1;
  }
  throw std::logic_error("report: no CSV column " + name);
}

// gnuplot's name for a CSV column's value: "$5".
std::string field(const std::string& name) {
  std::string text = "$";
  text += std::to_string(column(name));
  return text;
}

}  // namespace

std::vector<std::string> csv_columns() {
  std::vector<std::string> c = {"name",
                                "group",
                                "kind",
                                "frames",
                                "median_ms",
                                "p99_ms",
                                "mean_error",
                                "max_error",
                                "max_normal_error_deg",
                                "max_displacement",
                                "probe_inside"};
  deform::for_each_guard(deform::GuardCounts{}, [&](const char* name, std::uint32_t) { c.push_back(name); });
  c.push_back("plotted");
  c.push_back("pareto");
  return c;
}

void write_csv(const std::string& path, const std::vector<Row>& rows) {
  std::ofstream out = open(path);
  const std::vector<std::string> columns = csv_columns();
  for (std::size_t k = 0; k < columns.size(); ++k) out << (k ? "," : "") << columns[k];
  out << "\n";
  for (const Row& r : rows) {
    // The front's two axes round-trip exactly (%.17g), so a reader recomputing the front from the
    // CSV compares the numbers the report compared.
    out << r.name << "," << r.group << "," << kind_name(r.kind) << "," << r.frames << "," << g(r.median_ms, "%.17g")
        << "," << g(r.p99_ms, "%.6g") << "," << g(r.mean_error, "%.17g") << "," << g(r.max_error, "%.6g") << ","
        << g(r.max_normal_error_deg, "%.6g") << "," << g(r.max_displacement, "%.6g") << "," << r.probe_inside;
    deform::for_each_guard(r.guards, [&](const char*, std::uint32_t v) { out << "," << v; });
    out << "," << (plotted(r) ? 1 : 0) << "," << (r.pareto ? 1 : 0) << "\n";
  }
  if (!out) throw std::runtime_error("cannot write " + path);
}

void write_markdown(const std::string& path, const std::vector<Row>& rows, const ReportContext& context,
                    const std::string& plot_note) {
  std::ofstream out = open(path);
  out << "# Error against run time\n\n"
      << "Session `" << context.session << "` on `" << context.model << "` (" << context.points << " points, "
      << context.steps << " steps). Errors are point distances over the bounding-box diagonal against the exact "
      << "computation (double, fresh nearest-point search, global region, the session's kernel); per-frame rows "
      << "start every frame from the exact state, session rows compare the end of a whole session. Times are "
      << "one frame on this machine, same run.\n\n";
  out << (plot_note.empty() ? "![error against time](pareto.png)\n\n" : "No plot: " + plot_note + "\n\n");
  out << "| row | kind | frames | median ms | p99 ms | mean error | max error | max normal error | probe inside | "
         "guards | Pareto |\n| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | --- | :-: |\n";
  for (const Row& r : rows) {
    std::string guards;
    deform::for_each_guard(r.guards, [&](const char* name, std::uint32_t v) {
      if (v == 0) return;
      if (!guards.empty()) guards += ", ";
      guards.append(name).append(" ").append(std::to_string(v));
    });
    const bool timed_only = r.kind == RowKind::kTimeOnly;
    out << "| " << r.name << " | " << kind_name(r.kind) << " | " << r.frames << " | " << g(r.median_ms) << " | "
        << g(r.p99_ms) << " | " << (timed_only ? "(exact)" : g(r.mean_error, "%.3g")) << " | "
        << (timed_only ? "" : g(r.max_error, "%.3g")) << " | "
        << (timed_only ? "" : g(r.max_normal_error_deg, "%.3g") + "°") << " | " << r.probe_inside << " | "
        << (guards.empty() ? "none" : guards) << " | " << (r.pareto ? "yes" : "") << " |\n";
  }
  out << "\n## Reading\n\n";
  if (const Row* f = find(rows, "float")) {
    out << "- Float alone: mean " << g(f->mean_error, "%.2g") << ", max " << g(f->max_error, "%.2g")
        << " of the diagonal, " << g(f->max_displacement > 0 ? f->max_error / f->max_displacement : 0.0, "%.2g")
        << " of the largest displacement (" << g(f->max_displacement, "%.3g") << " of the diagonal).\n";
  }
  std::string regions;
  for (const Row& r : rows) {
    if (r.group != "region") continue;
    if (!regions.empty()) regions += "; ";
    regions.append(r.name).append(" ").append(g(r.mean_error, "%.2g"));
  }
  if (!regions.empty()) out << "- Region, mean error: " << regions << ".\n";
  std::string reduced;
  for (const Row& r : rows) {
    if (r.group != "reduced set") continue;
    if (!reduced.empty()) reduced += "; ";
    reduced.append(r.name).append(" ").append(percent(r.mean_error));
  }
  if (!reduced.empty()) {
    out << "- Session end, mean error: " << reduced << " (the thesis measured 0.08 % to 0.32 % for its reduced "
        << "set).\n";
  }
  std::string front;
  for (const Row& r : rows) {
    if (!r.pareto) continue;
    if (!front.empty()) front += ", ";
    front += r.name;
  }
  out << "- Pareto front (median time against mean error): " << (front.empty() ? "empty" : front) << ".\n";
  if (!out) throw std::runtime_error("cannot write " + path);
}

std::string plot_pareto(const std::string& dir, const std::vector<Row>& rows, const ReportContext& context) {
  if (std::system("command -v gnuplot >/dev/null 2>&1") != 0) {
    return "gnuplot was not found (scripts/setup.sh installs gnuplot-nox); report.md and report.csv are written";
  }
  const std::string script = dir + "/pareto.gp";
  {
    std::ofstream out = open(script);
    const std::string x = std::to_string(column("median_ms"));
    const std::string y = field("mean_error");
    const std::string on = field("plotted");
    out << "# Written by sculpt report: error against time from report.csv.\n"
        << "set terminal pngcairo size 1400,900 font ',10'\n"
        << "set output 'pareto.png'\n"
        << "set datafile separator ','\n"
        << "set logscale xy\nset format y '10^{%L}'\nset grid\n"
        << "set xlabel 'frame time, median (ms)'\n"
        << "set ylabel 'mean point error / bounding-box diagonal'\n"
        << "set title \"" << context.model << " (" << context.points << " points, " << context.steps
        << " steps)\" noenhanced\n"
        << "set key top right\n"
        << "kind(k) = strcol(" << column("kind") << ") eq k\n"
        << "plot 'report.csv' every ::1 using " << x << ":(" << on << "==1 && kind('per-frame') ? " << y
        << " : 1/0) with points pt 7 ps 1.3 title 'per-frame rows (one frame from the exact state)', \\\n"
        << "     '' every ::1 using " << x << ":(" << on << "==1 && kind('session') ? " << y
        << " : 1/0) with points pt 5 ps 1.3 title 'session rows (a whole session, at its end)', \\\n"
        << "     '' every ::1 using " << x << ":(" << on << "==1 ? " << y
        << " : 1/0):1 with labels left offset 0.8,0.4 font ',8' noenhanced notitle, \\\n"
        << "     'pareto_front.dat' using 1:2 with lines lw 2 title 'Pareto front'\n";
  }
  // The front as a line needs its rows in order of time; gnuplot's own sorting (smooth unique)
  // drops the line at the rows the CSV filter leaves undefined.
  std::vector<const Row*> front;
  for (const Row& r : rows) {
    if (r.pareto) front.push_back(&r);
  }
  std::sort(front.begin(), front.end(), [](const Row* a, const Row* b) { return a->median_ms < b->median_ms; });
  {
    std::ofstream out = open(dir + "/pareto_front.dat");
    out << "# median_ms,mean_error: the Pareto front of report.csv, by time\n";
    for (const Row* r : front) out << g(r->median_ms, "%.17g") << "," << g(r->mean_error, "%.17g") << "\n";
  }
  const std::string command = "cd '" + dir + "' && gnuplot pareto.gp >gnuplot.log 2>&1";
  if (std::system(command.c_str()) != 0) return "gnuplot failed (see " + dir + "/gnuplot.log)";
  return "";
}

}  // namespace sculpt::tools::report
