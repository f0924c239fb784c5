#include "measure.hpp"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>

#include "approximations.hpp"
#include "exact_frame.hpp"
#include "model_error.hpp"
#include "sculpt/rt/transfer.hpp"

namespace sculpt::tools::report {
namespace {

double elapsed_ns(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - since).count();
}

// One approximation's deformer on a float model of its own, and what its frames measured.
struct Runner {
  Approximation approximation;
  deform::PointModel model;
  std::unique_ptr<deform::Deformer> deformer;
  Row row;
  std::vector<double> ns;
  double error_sum = 0.0;
};

void add_error(Row& row, double& sum, const ModelError& e) {
  sum += e.mean;
  row.max_error = std::max(row.max_error, e.max);
  row.max_normal_error_deg = std::max(row.max_normal_error_deg, e.max_normal_deg);
}

}  // namespace

std::vector<Row> per_frame_rows(const RecordedSession& session, ExactState& exact_end, const Progress& progress) {
  const double diagonal = session.initial.bounding_box_diagonal();
  const ExactFrame exact(session.initial, session.settings);
  std::vector<Runner> runners;
  double auto_radius = 0.0;
  for (double r : session.step_radius) auto_radius = auto_radius > 0.0 ? auto_radius : r;
  for (Approximation& a :
       approximations(session.settings, session.spacing, session.initial.has_normals(), auto_radius)) {
    Runner r;
    r.row.name = a.name;
    r.row.group = a.group;
    r.model = session.initial;
    r.approximation = std::move(a);
    runners.push_back(std::move(r));
  }
  // Built once the vector no longer moves: a deformer keeps a reference to its model.
  for (Runner& r : runners) r.deformer = std::make_unique<deform::Deformer>(r.model, r.approximation.settings);

  Row exact_row = labelled("exact", "reference", RowKind::kExact);
  Row fresh_index = labelled("float + k-d tree rebuilt each frame", "index", RowKind::kTimeOnly);
  std::vector<double> exact_ns, fresh_ns;
  // SCULPT_REPORT_TRACE set: every step of every row on stderr, to see where a row departs.
  const bool trace = std::getenv("SCULPT_REPORT_TRACE") != nullptr;
  ExactState state = ExactState::from(session.initial);
  const std::size_t total = session.steps.size();
  for (std::size_t k = 0; k < total; ++k) {
    const auto& probes = session.steps[k];
    ExactState next = state;
    const auto t0 = std::chrono::steady_clock::now();
    const ExactReport e = exact.step(next, probes);
    exact_ns.push_back(elapsed_ns(t0));
    exact_row.guards += e.guards;
    exact_row.probe_inside += e.probe_inside;
    exact_row.max_displacement = std::max(exact_row.max_displacement, e.max_displacement / diagonal);
    for (Runner& r : runners) {
      state.store(r.model);
      // A fresh index on the exact state is exact by construction; only the frame is timed.
      const auto t1 = std::chrono::steady_clock::now();
      r.deformer->rebuild_index();
      if (r.approximation.recorded_radius && session.step_radius[k] > 0.0) {
        r.deformer->set_region_radius(session.step_radius[k]);
      }
      const double rebuild = elapsed_ns(t1);
      const auto t2 = std::chrono::steady_clock::now();
      const deform::FrameReport& f = r.deformer->deform(probes);
      const double frame = elapsed_ns(t2);
      r.ns.push_back(frame);
      // The float row (the first) also times the index rebuilt every frame: the time-only row.
      if (&r == &runners.front()) fresh_ns.push_back(rebuild + frame);
      r.row.guards += f.guards;
      for (std::size_t p = 0; p < probes.size() && p < f.contacts.size(); ++p) {
        if (f.contacts[p].miss > r.approximation.settings.contact.min_source_distance) ++r.row.probe_inside;
      }
      const ModelError err = model_error(next, r.model, diagonal);
      add_error(r.row, r.error_sum, err);
      if (trace) {
        std::fprintf(stderr, "step %zu %-24s collisions %zu/%zu guards %u/%u max error %.3g\n", k, r.row.name.c_str(),
                     f.collisions, e.collisions, f.guards.total(), e.guards.total(), err.max);
      }
    }
    state = std::move(next);
    if (progress) progress("per-frame rows", k + 1, total);
  }
  exact_end = state;

  std::vector<Row> rows;
  set_times(exact_row, exact_ns);
  rows.push_back(exact_row);
  for (Runner& r : runners) {
    set_times(r.row, r.ns);
    r.row.mean_error = total > 0 ? r.error_sum / static_cast<double>(total) : 0.0;
    r.row.max_displacement = exact_row.max_displacement;
    rows.push_back(r.row);
  }
  set_times(fresh_index, fresh_ns);
  fresh_index.max_displacement = exact_row.max_displacement;
  rows.push_back(fresh_index);
  return rows;
}

std::vector<Row> session_rows(const rt::Scene& scene, const rt::SampleLog* samples, const RecordedSession& full,
                              const ExactState& exact_end, const std::vector<double>& ratios,
                              const Progress& progress) {
  const double diagonal = full.initial.bounding_box_diagonal();
  std::vector<Row> rows;
  auto judge = [&](Row& row, const deform::PointModel& result) {
    const ModelError e = model_error(exact_end, result, diagonal);
    row.mean_error = e.mean;
    row.max_error = e.max;
    row.max_normal_error_deg = e.max_normal_deg;
  };
  Row whole = labelled("session float 100 %", "reduced set", RowKind::kSession);
  set_times(whole, full.frame_ns);
  judge(whole, full.final_model);
  whole.guards = full.guards;
  rows.push_back(whole);
  // Whole sessions with the heuristics a per-frame row cannot judge over time: a region's
  // pinned band and stale normals both change where later frames find the surface.
  auto variant = [&](const std::string& name, const rt::Scene& changed) {
    const RecordedSession run = record_session(changed, samples);
    Row row = labelled(name, "session", RowKind::kSession);
    set_times(row, run.frame_ns);
    judge(row, run.final_model);
    row.guards = run.guards;
    rows.push_back(row);
  };
  for (double k : {10.0, 20.0}) {
    rt::Scene regional = scene;
    regional.heuristic.region = rt::RegionChoice::kRadius;
    regional.heuristic.region_radius = k * full.spacing;
    char name[48];
    std::snprintf(name, sizeof name, "session region %g sp", k);
    variant(name, regional);
  }
  if (full.initial.has_normals()) {
    rt::Scene stale = scene;
    stale.deform.carry_normals = false;
    variant("session normals off", stale);
    // The bounded normal update over a whole session: its per-frame bound adds up frame by frame.
    rt::Scene bounded = scene;
    bounded.deform.normal_skip_bound = 1e-2;
    variant("session normals bounded 0.01", bounded);
  }
  std::size_t done = 0;
  for (double ratio : ratios) {
    rt::Scene reduced = scene;
    reduced.heuristic.reduced_ratio = ratio;
    const RecordedSession sub = record_session(reduced, samples);
    deform::PointModel target = full.initial;
    rt::transfer(target, sub.records);
    char name[64];
    std::snprintf(name, sizeof name, "reduced %g %% (%zu pts)", ratio * 100.0, sub.initial.size());
    Row row = labelled(name, "reduced set", RowKind::kSession);
    set_times(row, sub.frame_ns);
    judge(row, target);
    row.guards = sub.guards;
    rows.push_back(row);
    if (progress) progress("session rows", ++done, ratios.size());
  }
  return rows;
}

}  // namespace sculpt::tools::report
