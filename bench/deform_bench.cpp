// One collision frame, end to end (collision detection, boundary conditions, solve, update),
// on the thesis's sphere and on real scans, in float and double, each printed at the end as a
// ratio to the yardsticks measured in the same run. Figures go to the README.
#include <benchmark/benchmark.h>
#include <malloc.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "sculpt/deform/deformer.hpp"
#include "sculpt/deform/field_worker.hpp"
#include "sculpt/deform/generators.hpp"
#include "sculpt/deform/model_io.hpp"
#include "sculpt/deform/model_scale.hpp"
#include "sculpt/deform/normals.hpp"
#include "sculpt/deform/point_index.hpp"
#include "sculpt/deform/spatial_order.hpp"
#include "sculpt/deform/weight_solver.hpp"
#include "ratio_report.hpp"
#include "yardstick.hpp"

namespace {

using namespace sculpt::deform;
namespace bench = sculpt::bench;

// Frames are timed by the steady clock around the deformer's call alone, and the untimed work
// (restoring the model) runs between: Google Benchmark's PauseTiming reads the CPU-time clock,
// a system call of about 1.3 us on these VMs (25 ns for the steady clock), and part of it
// landed in every timed frame, a tenth of the sphere's. The time is wall time, what the
// station's tick sees, and also counts the worker's share on two threads.
using FrameClock = std::chrono::steady_clock;

template <typename Frame>
decltype(auto) timed(benchmark::State& state, Frame&& run_frame) {
  const FrameClock::time_point start = FrameClock::now();
  decltype(auto) result = run_frame();
  state.SetIterationTime(std::chrono::duration<double>(FrameClock::now() - start).count());
  return result;
}

template <typename Run>
benchmark::internal::Benchmark* frame_row(const std::string& name, Run run) {
  return benchmark::RegisterBenchmark(name.c_str(), std::move(run))->UseManualTime();
}

// Bytes the heap holds now (small blocks and mmapped ones): the difference across a set-up is
// what that set-up keeps.
double heap_bytes() {
  const struct mallinfo2 m = mallinfo2();
  return static_cast<double>(m.uordblks + m.hblkhd);
}

// A name ending in this names the model before it, stored in Z order (sculpt order).
const std::string kZOrder = "+z";

// The file a model name reads: the name without its Z-order suffix. Probes are placed on this
// model's points, and the settings scaled to its spacing, so that a Z-ordered copy is pressed
// at the same places with the same settings.
std::string file_of(const std::string& name) {
  return name.ends_with(kZOrder) ? name.substr(0, name.size() - kZOrder.size()) : name;
}

// Models are loaded once and shared by every benchmark that names them.
const PointModel* load(const std::string& name) {
  static std::map<std::string, std::unique_ptr<PointModel>> cache;
  auto it = cache.find(name);
  if (it != cache.end()) return it->second.get();
  std::unique_ptr<PointModel> model;
  if (name != file_of(name)) {
    const PointModel* file = load(file_of(name));
    if (!file) return nullptr;
    model = std::make_unique<PointModel>(reordered(*file, spatial_order(*file)));
  } else if (name == "sphere") {
    model = std::make_unique<PointModel>(make_sphere());
  } else {
    const std::string path = std::string(SCULPT_SOURCE_DIR) + "/data/scans/" + name;
    if (!std::filesystem::exists(path)) return nullptr;
    model = std::make_unique<PointModel>(read_model(path));
    ensure_normals(*model);
  }
  return cache.emplace(name, std::move(model)).first->second.get();
}

// Fingers spread over the model: each probe starts two spacings outside a surface point and
// presses one spacing in, the way a glove finger meets the surface between two samples.
std::vector<ProbeMotion> spread_probes(const PointModel& m, std::size_t fingers, double spacing) {
  std::vector<ProbeMotion> probes;
  const std::size_t step = m.size() / (fingers + 1);
  for (std::size_t f = 0; f < fingers; ++f) {
    const std::size_t i = (f + 1) * step;
    const Vec3 a = m.position(i), n = m.normal(i);
    probes.push_back({a + n * (2.0 * spacing), a - n * spacing, std::nullopt});
  }
  return probes;
}

// The settings every frame here runs with, scaled to the model's spacing.
DeformSettings bench_settings(double spacing, Precision precision, double region_spacings, int threads = 1,
                              double normal_skip_bound = 0.0, bool fast_inverse_sqrt = false) {
  DeformSettings settings;
  settings.contact.bc_radius = spacing;
  settings.contact.min_source_distance = 0.25 * spacing;
  settings.contact.guard_distance = 1.5 * spacing;
  settings.field.precision = precision;
  settings.threads = threads;
  settings.field.normal_skip_bound = normal_skip_bound;
  settings.field.fast_inverse_sqrt = fast_inverse_sqrt;
  settings.measure_extremes = false;  // as the station runs it: a report's diagnostic, not the frame
  if (region_spacings > 0.0) {
    settings.region.kind = RegionSettings::Kind::kRadius;
    settings.region.radius = region_spacings * spacing;
  }
  return settings;
}

void frame(benchmark::State& state, const std::string& name, Precision precision, double region_spacings,
           int threads = 1, double normal_skip_bound = 0.0, bool fast_inverse_sqrt = false) {
  const PointModel* source = load(name);
  if (!source) {
    state.SkipWithError(("data/scans/" + file_of(name) + " missing: run scripts/fetch_scans.sh").c_str());
    return;
  }
  const std::size_t fingers = static_cast<std::size_t>(state.range(0));
  const double heap_before = heap_bytes();
  PointModel model = *source;
  const PointModel& file = *load(file_of(name));
  const double spacing = typical_spacing(file, PointIndex(file)).value;
  const DeformSettings settings =
      bench_settings(spacing, precision, region_spacings, threads, normal_skip_bound, fast_inverse_sqrt);
  Deformer deformer(model, settings);
  // The model's arrays and everything the deformer reserved (index, journal, buffers).
  const double bytes_per_point = (heap_bytes() - heap_before) / static_cast<double>(model.size());
  const std::vector<ProbeMotion> probes = spread_probes(file, fingers, spacing);
  std::size_t moved = 0, collisions = 0, normals_kept = 0;
  for (auto _ : state) {
    deformer.restore(*source);  // every iteration deforms the same undeformed model (untimed)
    const FrameReport& r = timed(state, [&]() -> const FrameReport& { return deformer.deform(probes); });
    benchmark::DoNotOptimize(model.x.data());
    moved = r.region_points;
    collisions = r.collisions;
    normals_kept = r.normals_bounded;
  }
  if (collisions != fingers) state.SkipWithError("not every finger collided");
  // Error against the exact full computation (every point, double): the price of the region
  // heuristic and of float arithmetic, relative to the largest exact displacement.
  PointModel exact = *source;
  DeformSettings exact_settings = settings;
  exact_settings.field.precision = Precision::kDouble;
  exact_settings.region = RegionSettings{};
  exact_settings.threads = 1;
  exact_settings.field.normal_skip_bound = 0.0;
  exact_settings.field.fast_inverse_sqrt = false;
  Deformer exact_deformer(exact, exact_settings);
  const double scale = exact_deformer.deform(probes).max_displacement;
  double worst = 0.0;
  for (std::size_t i = 0; i < model.size(); ++i) worst = std::max(worst, norm(model.position(i) - exact.position(i)));
  state.counters["err_vs_exact"] = scale > 0.0 ? worst / scale : 0.0;
  state.counters["points"] = static_cast<double>(model.size());
  state.counters["bytes/point"] = bytes_per_point;
  state.counters["moved"] = static_cast<double>(moved);
  if (normal_skip_bound > 0.0) state.counters["normals_kept"] = static_cast<double>(normals_kept);
  // The share of frames whose pass found the worker spinning rather than asleep (field_worker.hpp).
  if (const FieldWorker* worker = deformer.worker(); worker != nullptr && state.iterations() > 0) {
    state.counters["worker_awake"] =
        static_cast<double>(worker->tasks_met_awake()) / static_cast<double>(state.iterations());
  }
  state.counters["frames/s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

// A stroke, as the station runs one: every finger pressed half a spacing in, then slid `step`
// spacings a frame along the plane tangent at its start, half a step deeper each frame. The
// fast stroke (region20_stroke) slides half a spacing a frame (a twentieth, as sculpt check's
// slide, left half the fingers above the dent their last frame made: guarded, not pressing);
// the glide (region20_glide) a twentieth, about what the bundled scenes' fingers cover in a
// 1 kHz tick (the dragon press: 0.04 spacings), for 64 frames. Each frame deforms the one
// before's output, from where the deformer left each finger; on a curved scan some fingers
// leave the surface, so the row reports the collisions per frame. The model is restored
// (untimed) every `frames_per_stroke` frames. The single-press rows restore it before every
// frame, so each of their frames finds the index, the region's points and the buffers out of
// the caches; here, as in the station, all but a stroke's first frame find them where the
// frame before left them.
void stroke(benchmark::State& state, const std::string& name, double region_spacings, double step = 0.5,
            int frames_per_stroke = 16) {
  const PointModel* source = load(name);
  if (!source) {
    state.SkipWithError(("data/scans/" + file_of(name) + " missing: run scripts/fetch_scans.sh").c_str());
    return;
  }
  const std::size_t fingers = static_cast<std::size_t>(state.range(0));
  const PointModel& file = *load(file_of(name));
  const double heap_before = heap_bytes();
  PointModel model = *source;
  const double spacing = typical_spacing(file, PointIndex(file)).value;
  Deformer deformer(model, bench_settings(spacing, Precision::kFloat, region_spacings));
  const double bytes_per_point = (heap_bytes() - heap_before) / static_cast<double>(model.size());
  // Each finger's surface point a, its outward normal n and a direction t along the surface.
  std::vector<Vec3> at, out, along;
  for (const ProbeMotion& m : spread_probes(file, fingers, spacing)) {
    const Vec3 n = normalized(m.previous - m.current);
    const Vec3 a = m.current + n * spacing;
    const Vec3 axis = std::abs(n.x) < 0.5 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
    at.push_back(a);
    out.push_back(n);
    along.push_back(normalized(cross(n, axis)));
  }
  std::vector<ProbeMotion> motions(fingers);
  std::vector<Vec3> accepted(fingers);
  std::vector<std::optional<Vec3>> earlier(fingers);
  int k = frames_per_stroke;
  std::size_t frames = 0, collisions = 0, moved = 0, applied = 0;
  for (auto _ : state) {
    if (k == frames_per_stroke) {
      deformer.restore(*source);  // untimed
      for (std::size_t f = 0; f < fingers; ++f) {
        accepted[f] = at[f] + out[f] * (2.0 * spacing);
        earlier[f].reset();
      }
      k = 0;
    }
    for (std::size_t f = 0; f < fingers; ++f) {
      const Vec3 target = at[f] + along[f] * (step * spacing * k) - out[f] * ((0.5 + 0.5 * step * k) * spacing);
      motions[f] = ProbeMotion{accepted[f], target, earlier[f]};
    }
    const FrameReport& r = timed(state, [&]() -> const FrameReport& { return deformer.deform(motions); });
    benchmark::DoNotOptimize(model.x.data());
    for (std::size_t f = 0; f < fingers; ++f) {
      const ContactReport& c = r.contacts[f];
      earlier[f] = accepted[f];
      accepted[f] = c.state == ProbeState::kDropped ? motions[f].current : c.probe_after;
    }
    ++frames;
    ++k;
    collisions += r.collisions;
    moved += r.region_points;
    applied += deformer.frames().size();
  }
  if (collisions == 0) state.SkipWithError("no finger collided");
  const double per_frame = frames > 0 ? 1.0 / static_cast<double>(frames) : 0.0;
  state.counters["points"] = static_cast<double>(model.size());
  state.counters["moved"] = static_cast<double>(moved) * per_frame;
  state.counters["collisions/frame"] = static_cast<double>(collisions) * per_frame;
  state.counters["bytes/point"] = bytes_per_point;
  // Above 1 when frames were split into substeps (a fold averted), below when some moved nothing.
  state.counters["applied/frame"] = static_cast<double>(applied) * per_frame;
  state.counters["frames/s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

// The bare per-point loop: five Kelvin sources added to 100,000 points (the brief's 0.22 ms).
void bare_loop(benchmark::State& state, Precision precision) {
  PointModel model = make_sphere(100000);
  model.clear_normals();
  const Kernel kernel;
  std::vector<SourceForce> sources;
  for (int s = 0; s < 5; ++s) sources.push_back({{0.3 * s, 0.0, 1.5}, {0.0, 0.0, -1e-3}});
  for (auto _ : state) {
    benchmark::DoNotOptimize(
        apply_displacements(model, kernel, sources, {}, true, {precision, false}).max_displacement);
  }
  state.counters["points/s"] =
      benchmark::Counter(1e5 * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

// The weight solve alone: `sources` Kelvin sources just outside the unit sphere, each over a
// contact point, and `conditions` displacement conditions spread over the caps under them (the
// contacts' patches and a region's pinned band: 445 conditions is the 100k dragon's five-finger
// region frame, 7 the sphere's three-finger global one, and 15 one block, to show the small
// factor's solve apart from the rows).
void solve_only(benchmark::State& state) {
  const auto sources_count = static_cast<std::size_t>(state.range(0));
  const auto conditions_count = static_cast<std::size_t>(state.range(1));
  const Kernel kernel;
  std::vector<SourceSetup> sources;
  std::vector<Vec3> contacts;
  for (std::size_t s = 0; s < sources_count; ++s) {
    const double t = 2.0 * static_cast<double>(s) + 0.5;
    const Vec3 a = normalized(Vec3{std::cos(t), std::sin(t), 0.3 * static_cast<double>(s) - 0.6});
    contacts.push_back(a);
    sources.push_back({a * 1.05, a * -0.01});
  }
  std::vector<DisplacementCondition> conditions;
  for (std::size_t i = 0; i < conditions_count; ++i) {
    const Vec3& a = contacts[i % sources_count];
    const double t = 0.7 * static_cast<double>(i);
    const Vec3 offset{0.1 * std::cos(t), 0.1 * std::sin(t), 0.05 * std::cos(1.3 * t)};
    conditions.push_back({normalized(a + offset), i < sources_count ? a * -0.01 : Vec3{}, 1.0});
  }
  const WeightSolver solver;
  std::vector<Vec3> weights(sources_count), effective(sources_count);
  for (auto _ : state) {
    benchmark::DoNotOptimize(solver.solve(kernel, sources, conditions, {}, weights, effective).residual);
  }
}

// A scan indexed as a frame's deformer indexes it, with its typical spacing, for the rows that
// time the index's queries alone; empty (and the row skipped) when the scan is missing.
struct IndexedScan {
  const PointModel* model = nullptr;
  std::unique_ptr<PointIndex> index;
  double spacing = 0.0;
};

IndexedScan indexed_scan(benchmark::State& state, const std::string& name) {
  IndexedScan scan;
  scan.model = load(name);
  if (!scan.model) {
    state.SkipWithError(("data/scans/" + file_of(name) + " missing: run scripts/fetch_scans.sh").c_str());
    return scan;
  }
  scan.index = std::make_unique<PointIndex>(*scan.model);
  scan.spacing = typical_spacing(*scan.model, *scan.index).value;
  return scan;
}

// The region's neighbourhood queries alone, as a five-finger region frame asks them: a ball of
// 20 spacings around each of the bench's five contact points, after every point moved up to
// `drift_spacings` (the drift a stroke has built up since the index's snapshot; none moved as
// far, so the answers are those of the snapshot and the query pays only for the widening).
void region_query(benchmark::State& state, const std::string& name, double drift_spacings) {
  const IndexedScan scan = indexed_scan(state, name);
  if (!scan.model) return;
  std::vector<Vec3> centres;
  for (const ProbeMotion& p : spread_probes(*scan.model, 5, scan.spacing))
    centres.push_back(p.previous + (p.current - p.previous) * (2.0 / 3.0));
  std::vector<std::uint32_t> out;
  out.reserve(scan.model->size());
  std::size_t found = 0;
  for (auto _ : state) {
    found = 0;
    for (const Vec3& c : centres) {
      scan.index->within_radius(*scan.model, c, 20.0 * scan.spacing, out, drift_spacings * scan.spacing,
                                /*ascending=*/false);
      found += out.size();
    }
    benchmark::DoNotOptimize(out.data());
  }
  state.counters["found"] = static_cast<double>(found);
}

// The contact's nearest-point queries alone: from each of the bench's five probes before and
// after its move (two spacings out and one in) and at its contact, after every point moved up
// to `drift_spacings` (as in region_query, the answers are the snapshot's).
void nearest_query(benchmark::State& state, const std::string& name, double drift_spacings) {
  const IndexedScan scan = indexed_scan(state, name);
  if (!scan.model) return;
  std::vector<Vec3> queries;
  for (const ProbeMotion& p : spread_probes(*scan.model, 5, scan.spacing)) {
    queries.push_back(p.previous);
    queries.push_back(p.current);
    queries.push_back(p.previous + (p.current - p.previous) * (2.0 / 3.0));
  }
  double sum = 0.0;
  for (auto _ : state) {
    sum = 0.0;
    for (const Vec3& q : queries) sum += scan.index->nearest(*scan.model, q, drift_spacings * scan.spacing).distance;
    benchmark::DoNotOptimize(sum);
  }
  state.counters["queries"] = static_cast<double>(queries.size());
}

// The yardsticks on as many points as each model has (bench/yardstick.hpp).
void yardsticks(std::size_t points) {
  benchmark::RegisterBenchmark(bench::bare_name(points).c_str(), [points](benchmark::State& state) {
    bench::FloatPoints p = bench::sphere_points(points);
    const bench::FiveForces forces = bench::five_forces();
    for (auto _ : state) {
      bench::bare_kelvin_pass(p, forces);
      benchmark::DoNotOptimize(p.x.data());
      benchmark::ClobberMemory();
    }
  })->Unit(benchmark::kMicrosecond);
  benchmark::RegisterBenchmark(bench::stream_name(points).c_str(), [points](benchmark::State& state) {
    bench::FloatPoints p = bench::sphere_points(points);
    for (auto _ : state) {
      bench::stream_pass(p);
      benchmark::DoNotOptimize(p.x.data());
      benchmark::ClobberMemory();
    }
  })->Unit(benchmark::kMicrosecond);
}

void register_all() {
  using benchmark::RegisterBenchmark;
  const auto ms = benchmark::kMillisecond;
  for (std::size_t points : {3203u, 54559u, 100250u, 437645u}) yardsticks(points);
  RegisterBenchmark("Solve/sources_conditions", solve_only)
      ->Args({1, 59})
      ->Args({3, 7})
      ->Args({5, 15})
      ->Args({5, 445})
      ->Args({5, 1000})
      ->Unit(benchmark::kMicrosecond);
  for (const char* scan : {"dragon_100250.ply", "dragon_437645.ply"}) {
    const std::string name = scan;
    RegisterBenchmark(("RegionQuery/" + name + "/drift_spacings").c_str(),
                      [name](benchmark::State& s) { region_query(s, name, static_cast<double>(s.range(0))); })
        ->Arg(0)
        ->Arg(2)
        ->Unit(benchmark::kMicrosecond);
    RegisterBenchmark(("NearestQuery/" + name + "/drift_spacings").c_str(),
                      [name](benchmark::State& s) { nearest_query(s, name, static_cast<double>(s.range(0))); })
        ->Arg(0)
        ->Arg(2)
        ->Unit(benchmark::kMicrosecond);
  }
  for (auto [precision, tag] : {std::pair{Precision::kFloat, "float"}, std::pair{Precision::kDouble, "double"}}) {
    const Precision p = precision;
    RegisterBenchmark((std::string("BareLoop5x100k/") + tag).c_str(), [p](benchmark::State& s) {
      bare_loop(s, p);
    })->Unit(benchmark::kMicrosecond);
    frame_row(std::string("Sphere3203/global/") + tag, [p](benchmark::State& s) { frame(s, "sphere", p, 0.0); })
        ->Arg(1)
        ->Arg(2)
        ->Arg(3)
        ->Unit(benchmark::kMicrosecond);
    if (p == Precision::kFloat) {
      frame_row(std::string("Sphere3203/global_fast_isqrt/") + tag,
                [p](benchmark::State& s) { frame(s, "sphere", p, 0.0, 1, 0.0, true); })
          ->Arg(3)
          ->Unit(benchmark::kMicrosecond);
      // A region of 20 spacings holds 91 % of the sphere: run as the global frame, the cheaper
      // (RegionSettings::global_when_cheaper), where the region itself took twice its time.
      frame_row(std::string("Sphere3203/region20/") + tag, [p](benchmark::State& s) { frame(s, "sphere", p, 20.0); })
          ->Arg(3)
          ->Unit(benchmark::kMicrosecond);
    }
    for (const char* scan : {"snowden_54559.ply", "dragon_100250.ply", "dragon_437645.ply"}) {
      const std::string name = scan;
      frame_row("Scan/" + name + "/global/" + tag, [p, name](benchmark::State& s) { frame(s, name, p, 0.0); })
          ->Arg(1)
          ->Arg(5)
          ->Unit(ms);
      // A five-finger global row on `model` (this scan, or its Z-ordered copy).
      const auto global_row = [&](const std::string& row, const std::string& model, int threads, double bound) {
        auto* b = frame_row("Scan/" + name + "/" + row + "/" + tag, [p, model, threads, bound](benchmark::State& s) {
          frame(s, model, p, 0.0, threads, bound);
        });
        b->Arg(5)->Unit(ms);
      };
      // Both cores: the deformer's worker takes half of the displacement pass.
      global_row("global_2threads", name, 2, 0.0);
      // The bounded normal update (FieldOptions::normal_skip_bound = 1e-2: a kept normal is
      // within 1.0e-2 rad of the carried one), on one core and on both.
      global_row("global_bounded", name, 1, 1e-2);
      global_row("global_bounded_2threads", name, 2, 1e-2);
      // The same global frames on the scan stored in Z order (sculpt order): a register of 16
      // points in a row is then 16 neighbours, so the bounded pass finds whole registers far
      // from every finger where the file's order mixes near and far points in each.
      if (p == Precision::kFloat) {
        global_row("global_2threads_zorder", name + kZOrder, 2, 0.0);
        global_row("global_bounded_zorder", name + kZOrder, 1, 1e-2);
        global_row("global_bounded_2threads_zorder", name + kZOrder, 2, 1e-2);
      }
      // 1/r from the processor's estimate (FieldOptions::fast_inverse_sqrt; float only).
      if (p == Precision::kFloat) {
        frame_row("Scan/" + name + "/global_fast_isqrt/" + tag,
                  [p, name](benchmark::State& s) { frame(s, name, p, 0.0, 1, 0.0, true); })
            ->Arg(5)
            ->Unit(ms);
        frame_row("Scan/" + name + "/global_fast_isqrt_2threads/" + tag,
                  [p, name](benchmark::State& s) { frame(s, name, p, 0.0, 2, 0.0, true); })
            ->Arg(5)
            ->Unit(ms);
        // Both approximations: most points then need their displacement alone, whose cost is
        // the square root and division per source that the estimate replaces.
        for (const int threads : {1, 2}) {
          frame_row("Scan/" + name +
                        (threads == 1 ? "/global_bounded_fast_isqrt/" : "/global_bounded_fast_isqrt_2threads/") + tag,
                    [p, name, threads](benchmark::State& s) { frame(s, name, p, 0.0, threads, 1e-2, true); })
              ->Arg(5)
              ->Unit(ms);
        }
      }
      frame_row("Scan/" + name + "/region20/" + tag, [p, name](benchmark::State& s) { frame(s, name, p, 20.0); })
          ->Arg(1)
          ->Arg(5)
          ->Unit(ms);
      if (p == Precision::kFloat) {
        frame_row("Scan/" + name + "/region20_stroke/" + tag, [name](benchmark::State& s) { stroke(s, name, 20.0); })
            ->Arg(5)
            ->Unit(ms);
        frame_row("Scan/" + name + "/region20_glide/" + tag,
                  [name](benchmark::State& s) { stroke(s, name, 20.0, 0.05, 64); })
            ->Arg(5)
            ->Unit(ms);
        // The same frames on the scan stored in Z order (sculpt order), pressed at the same points.
        const std::string ordered = name + kZOrder;
        frame_row("Scan/" + name + "/region20_zorder/" + tag,
                  [p, ordered](benchmark::State& s) { frame(s, ordered, p, 20.0); })
            ->Arg(5)
            ->Unit(ms);
        frame_row("Scan/" + name + "/region20_stroke_zorder/" + tag,
                  [ordered](benchmark::State& s) { stroke(s, ordered, 20.0); })
            ->Arg(5)
            ->Unit(ms);
      }
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  register_all();
  benchmark::Initialize(&argc, argv);
  sculpt::bench::RatioReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  benchmark::Shutdown();
  return 0;
}
