#include "check_cases.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <stdexcept>

#include "sculpt/deform/generators.hpp"
#include "sculpt/deform/model_io.hpp"
#include "sculpt/deform/model_scale.hpp"
#include "sculpt/deform/normal_check.hpp"
#include "sculpt/deform/normals.hpp"
#include "sculpt/deform/point_index.hpp"

namespace sculpt::tools::check {
namespace {

using deform::Vec3;
using Model = std::shared_ptr<const deform::PointModel>;

// ---- models (base coordinates) ------------------------------------------------------------

// A sheet of nx x ny points in z = 0 with spacings sx, sy, normals +z. With sy several times sx
// the bc ball around a point holds one row only: a collinear boundary set.
deform::PointModel make_rows(std::size_t nx, std::size_t ny, double sx, double sy) {
  deform::PointModel m;
  m.resize(nx * ny, /*with_normals=*/true, /*with_colors=*/false);
  for (std::size_t j = 0; j < ny; ++j) {
    for (std::size_t i = 0; i < nx; ++i) {
      const double x = (static_cast<double>(i) - 0.5 * static_cast<double>(nx - 1)) * sx;
      const double y = (static_cast<double>(j) - 0.5 * static_cast<double>(ny - 1)) * sy;
      m.set_position(j * nx + i, {x, y, 0.0});
      m.set_normal(j * nx + i, {0.0, 0.0, 1.0});
    }
  }
  return m;
}

// The sphere with every point within `radius` of the pole appended a second time, bit for bit.
deform::PointModel with_duplicates_near(deform::PointModel m, const Vec3& where, double radius) {
  const std::size_t n = m.size();
  for (std::size_t i = 0; i < n; ++i) {
    if (norm(m.position(i) - where) > radius) continue;
    m.push_back(m.position(i));
    m.set_normal(m.size() - 1, m.normal(i));
  }
  return m;
}

std::size_t nearest_point(const deform::PointModel& m, const Vec3& q) {
  std::size_t best = 0;
  for (std::size_t i = 1; i < m.size(); ++i) {
    if (squared_norm(m.position(i) - q) < squared_norm(m.position(best) - q)) best = i;
  }
  return best;
}

std::size_t highest_along(const deform::PointModel& m, const Vec3& axis) {
  std::size_t best = 0;
  for (std::size_t i = 1; i < m.size(); ++i) {
    if (dot(m.position(i), axis) > dot(m.position(best), axis)) best = i;
  }
  return best;
}

// ---- single frames --------------------------------------------------------------------------

// One degenerate frame at model point `at`: fingers placed at `previous`, pressed to `current`,
// both given as functions of the contact A, its outward normal n, a tangent t and the spacing s
// (all read from the runner, so they are right in every frame and scale).
struct Local {
  Vec3 a, n, t;
  double s, dd;
};
using Placement = std::function<void(const Local&, std::vector<Vec3>& previous, std::vector<Vec3>& current)>;

std::function<void(StrokeRunner&)> single_frame(std::size_t at, Vec3 normal, Placement placement) {
  return [at, normal, placement](StrokeRunner& r) {
    Local l{r.point(at), normalized(normal), {}, r.spacing(), r.delta_d()};
    l.t = normalized(cross(l.n, std::abs(l.n.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0}));
    std::vector<Vec3> previous, current;
    placement(l, previous, current);
    r.place(previous);
    r.press(current);
  };
}

// ---- strokes ----------------------------------------------------------------------------------

// A series of pushes at random material points among `sites` (fixed seed): hover 2 spacings out
// along the oracle's normal there, press 0.25-1.5 spacings in, lift back out. Three frames a push;
// the dents add up, which is what makes the thesis's long series extreme.
std::function<void(StrokeRunner&)> push_series(std::vector<std::size_t> sites, int pushes, unsigned seed) {
  return [sites, pushes, seed](StrokeRunner& r) {
    std::mt19937 rng(seed);
    std::uniform_int_distribution<std::size_t> pick(0, sites.size() - 1);
    std::uniform_real_distribution<double> depth(0.25, 1.5);
    const double s = r.spacing();
    bool placed = false;
    for (int k = 0; k < pushes; ++k) {
      const Vec3 p = r.point(sites[pick(rng)]);
      const Vec3 n = r.surface(p).normal;
      const Vec3 hover = p + n * (2.0 * s);
      const Vec3 in = p - n * (depth(rng) * s);
      if (!placed) {
        r.place(std::span(&hover, 1));
        placed = true;
      } else {
        r.press(std::span(&hover, 1));
      }
      r.press(std::span(&in, 1));
      const Vec3 lift = r.finger(0) + n * (2.0 * s);
      r.press(std::span(&lift, 1));
    }
  };
}

// Fingers moving radially into the unit sphere from radius `from` in `frames` steps of `step`.
std::function<void(StrokeRunner&)> radial_squeeze(std::vector<Vec3> directions, double from, double step, int frames) {
  return [directions, from, step, frames](StrokeRunner& r) {
    std::vector<Vec3> at;
    for (const Vec3& d : directions) at.push_back(normalized(d) * from);
    r.place(at);
    for (int k = 1; k <= frames; ++k) {
      for (std::size_t f = 0; f < at.size(); ++f) at[f] = normalized(directions[f]) * (from - step * k);
      r.press(at);
    }
  };
}

// One finger pressed half a spacing into the z = 0 sheet and slid along x by half a spacing a
// frame, going a twentieth of a spacing deeper each frame: the dent has to travel with it. (At
// constant depth each new position sits exactly level with the dent's bottom, and float
// round-off alone decides whether it touches: a knife edge, not a stroke.)
std::function<void(StrokeRunner&)> slide(double x_from, int frames) {
  return [x_from, frames](StrokeRunner& r) {
    const double s = r.spacing();
    const Vec3 hover{x_from, 0.0, 2.0 * s};
    r.place(std::span(&hover, 1));
    for (int k = 0; k <= frames; ++k) {
      const Vec3 p{x_from + 0.5 * s * k, 0.0, -(0.5 + 0.05 * k) * s};
      r.press(std::span(&p, 1));
    }
    const Vec3 lift = r.finger(0) + Vec3{0.0, 0.0, 2.0 * s};
    r.press(std::span(&lift, 1));
  };
}

const std::vector<Vec3> kHandOne = {{-1, 0, 0.4}, {1, -0.45, 0.4}, {1, -0.15, 0.4}, {1, 0.15, 0.4}, {1, 0.45, 0.4}};
const std::vector<Vec3> kHandTwo = {
    {0, -1, -0.5}, {-0.45, 1, -0.5}, {-0.15, 1, -0.5}, {0.15, 1, -0.5}, {0.45, 1, -0.5}};

// ---- the settings axes --------------------------------------------------------------------

std::string describe(const CaseSettings& s) {
  char text[160];
  std::snprintf(text, sizeof text, "nu=%g %s/%s/%s G=%.0e x%g", s.poisson_ratio,
                s.kernel == deform::KernelKind::kKelvin ? "kelvin" : "regular",
                s.form == deform::WeightForm::kForce ? "force" : "scale",
                s.precision == deform::Precision::kFloat ? "float" : "double", s.shear_modulus, s.scale);
  return text;
}

const double kPoisson[] = {-0.9, 0.0, 0.3, 0.45, 0.4999, 0.5};

// Quick: every axis varied one at a time from the defaults, to its extremes. Full: the product
// of nu, kernel, form and precision, and G and scale each over their whole range.
std::vector<CaseSettings> settings_axes(bool quick) {
  std::vector<CaseSettings> out;
  const CaseSettings base;
  if (quick) {
    for (double nu : kPoisson) {
      CaseSettings s = base;
      s.poisson_ratio = nu;
      out.push_back(s);
    }
    CaseSettings s = base;
    s.kernel = deform::KernelKind::kRegularized;
    out.push_back(s);
    s = base;
    s.form = deform::WeightForm::kScale;
    out.push_back(s);
    s = base;
    s.precision = deform::Precision::kDouble;
    out.push_back(s);
    for (double g : {1e2, 1e12}) {
      s = base;
      s.shear_modulus = g;
      out.push_back(s);
    }
    for (double k : {1e-3, 1e3}) {
      s = base;
      s.scale = k;
      out.push_back(s);
    }
    return out;
  }
  for (double nu : kPoisson) {
    for (auto kernel : {deform::KernelKind::kKelvin, deform::KernelKind::kRegularized}) {
      for (auto form : {deform::WeightForm::kForce, deform::WeightForm::kScale}) {
        for (auto precision : {deform::Precision::kFloat, deform::Precision::kDouble}) {
          CaseSettings s = base;
          s.poisson_ratio = nu;
          s.kernel = kernel;
          s.form = form;
          s.precision = precision;
          out.push_back(s);
        }
      }
    }
  }
  for (double g : {1e2, 1e4, 1e6, 1e8, 1e10, 1e12}) {
    CaseSettings s = base;
    s.shear_modulus = g;
    out.push_back(s);
  }
  for (double k : {1e-3, 1e-2, 1e-1, 1e1, 1e2, 1e3}) {
    CaseSettings s = base;
    s.scale = k;
    out.push_back(s);
  }
  return out;
}

// The sheet with every point moved in its plane by up to 1 % of the pitch (fixed seed). A
// perfect lattice puts points exactly at the bc radius and probes exactly between two points,
// so float round-off under a shift or a scaling decides ties and a stroke's invariants would
// measure the ties, not the physics.
deform::PointModel jittered(deform::PointModel m, double amount) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> d(-amount, amount);
  for (std::size_t i = 0; i < m.size(); ++i) m.set_position(i, m.position(i) + Vec3{d(rng), d(rng), 0.0});
  return m;
}

}  // namespace

std::vector<CaseSpec> make_cases(const SweepOptions& options) {
  const Model sphere = std::make_shared<const deform::PointModel>(deform::make_sphere(3203));
  const Model sheet = std::make_shared<const deform::PointModel>(deform::make_plane_patch(41, 0.05));
  const Model slide_sheet = std::make_shared<const deform::PointModel>(jittered(*sheet, 0.01 * 0.05));
  const Model rows = std::make_shared<const deform::PointModel>(make_rows(41, 9, 0.05, 0.2));
  const std::size_t pole = highest_along(*sphere, {0, 0, 1});
  const Vec3 pole_normal = sphere->position(pole);
  const Model doubled =
      std::make_shared<const deform::PointModel>(with_duplicates_near(*sphere, sphere->position(pole), 0.2));
  const std::size_t sheet_middle = nearest_point(*sheet, {});
  const std::size_t rows_middle = nearest_point(*rows, {});
  const Outside convex{Outside::Kind::kAwayFromCentroid, {}};
  const Outside up{Outside::Kind::kDirection, {0, 0, 1}};
  // The mesh oracle's surfaces, from the undeformed points: hulls of the convex shapes, Delaunay
  // triangulations of the sheets in their plane, wound toward their outside.
  using Mesh = std::shared_ptr<const SurfaceMesh>;
  const Mesh sphere_mesh = std::make_shared<const SurfaceMesh>(convex_hull_mesh(*sphere));
  const Mesh doubled_mesh = std::make_shared<const SurfaceMesh>(convex_hull_mesh(*doubled));
  const Mesh sheet_surface = std::make_shared<const SurfaceMesh>(sheet_mesh(*sheet, up.direction));
  const Mesh slide_surface = std::make_shared<const SurfaceMesh>(sheet_mesh(*slide_sheet, up.direction));
  const Mesh rows_surface = std::make_shared<const SurfaceMesh>(sheet_mesh(*rows, up.direction));

  struct Single {
    const char* name;
    Model model;
    std::size_t at;
    Vec3 normal;
    Outside outside;
    Mesh mesh;
    double bc_factor;
    Placement placement;
  };
  const std::vector<Single> singles = {
      {"probe_on_point", sphere, pole, pole_normal, convex, sphere_mesh, 1.0,
       [](const Local& l, auto& prev, auto& cur) {
         prev = {l.a + l.n * (2 * l.s)};
         cur = {l.a};
       }},
      {"previous_on_point", sphere, pole, pole_normal, convex, sphere_mesh, 1.0,
       [](const Local& l, auto& prev, auto& cur) {
         prev = {l.a};
         cur = {l.a - l.n * (0.5 * l.s)};
       }},
      {"source_1e-6_above", sphere, pole, pole_normal, convex, sphere_mesh, 1.0,
       [](const Local& l, auto& prev, auto& cur) {
         prev = {l.a + l.n * 1e-6};
         cur = {l.a - l.n * (0.5 * l.s)};
       }},
      {"two_fingers_closer_than_dd", sphere, pole, pole_normal, convex, sphere_mesh, 1.0,
       [](const Local& l, auto& prev, auto& cur) {
         prev = {l.a + l.n * (2 * l.s) + l.t * (0.3 * l.dd), l.a + l.n * (2 * l.s) - l.t * (0.3 * l.dd)};
         cur = {l.a - l.n * (0.5 * l.s) + l.t * (0.3 * l.dd), l.a - l.n * (0.5 * l.s) - l.t * (0.3 * l.dd)};
       }},
      {"grazing", sphere, pole, pole_normal, convex, sphere_mesh, 1.0,
       [](const Local& l, auto& prev, auto& cur) {
         prev = {l.a + l.t * (2 * l.s)};
         cur = {l.a - l.n * (1e-3 * l.s)};
       }},
      {"tangential", sphere, pole, pole_normal, convex, sphere_mesh, 1.0,
       [](const Local& l, auto& prev, auto& cur) {
         prev = {l.a + l.t * (1.5 * l.s) + l.n * (0.3 * l.s)};
         cur = {l.a - l.t * (1.5 * l.s) - l.n * (0.3 * l.s)};
       }},
      {"duplicate_points", doubled, pole, pole_normal, convex, doubled_mesh, 1.0,
       [](const Local& l, auto& prev, auto& cur) {
         prev = {l.a + l.n * (2 * l.s)};
         cur = {l.a - l.n * (0.5 * l.s)};
       }},
      {"collinear_bc_set",
       rows,
       rows_middle,
       {0, 0, 1},
       up,
       rows_surface,
       1.5,
       [](const Local& l, auto& prev, auto& cur) {
         prev = {l.a + l.n * (2 * l.s)};
         cur = {l.a - l.n * (0.5 * l.s)};
       }},
      {"single_point_bc_set",
       sheet,
       sheet_middle,
       {0, 0, 1},
       up,
       sheet_surface,
       0.4,
       [](const Local& l, auto& prev, auto& cur) {
         prev = {l.a + l.n * (2 * l.s)};
         cur = {l.a - l.n * (0.5 * l.s)};
       }},
  };

  std::vector<CaseSpec> cases;
  const auto axes = settings_axes(options.quick);
  for (const Single& single : singles) {
    for (CaseSettings s : axes) {
      s.bc_factor = single.bc_factor;
      CaseSpec c;
      c.group = single.name;
      c.name = std::string(single.name) + " " + describe(s);
      c.settings = s;
      c.model = single.model;
      c.outside = single.outside;
      c.mesh = single.mesh;
      c.drive = single_frame(single.at, single.normal, single.placement);
      cases.push_back(std::move(c));
    }
  }

  std::vector<std::size_t> cap;  // the sphere within 50 degrees of the pole
  for (std::size_t i = 0; i < sphere->size(); ++i) {
    if (sphere->position(i).z > std::cos(50.0 * M_PI / 180.0)) cap.push_back(i);
  }
  struct Stroke {
    std::string name;
    Model model;
    Outside outside;
    Mesh mesh;
    std::function<void(StrokeRunner&)> drive;
  };
  std::vector<Stroke> strokes = {
      {"sphere_340_pushes", sphere, convex, sphere_mesh, push_series(cap, 340, 7)},
      {"sheet_slide", slide_sheet, up, slide_surface, slide(-0.5, 40)},
      {"straight_push_1.0_deep", sphere, convex, sphere_mesh, radial_squeeze({{0, 0, 1}}, 1.02, 0.02, 50)},
      {"five_fingers_squeeze", sphere, convex, sphere_mesh, radial_squeeze(kHandOne, 1.06, 0.01, 30)},
  };
  std::vector<Vec3> ten = kHandOne;
  ten.insert(ten.end(), kHandTwo.begin(), kHandTwo.end());
  strokes.push_back({"two_hands_ten_fingers", sphere, convex, sphere_mesh, radial_squeeze(ten, 1.06, 0.01, 30)});
  // The thesis's strokes over every setting in the full sweep; defaults and the quick axes'
  // extremes are enough for a smoke run.
  std::vector<CaseSettings> stroke_axes = settings_axes(true);
  if (options.quick) stroke_axes = {CaseSettings{}};
  for (const Stroke& stroke : strokes) {
    for (const CaseSettings& s : stroke_axes) {
      CaseSpec c;
      c.group = stroke.name;
      c.name = stroke.name + " " + describe(s);
      c.stroke = true;
      c.settings = s;
      c.model = stroke.model;
      c.outside = stroke.outside;
      c.mesh = stroke.mesh;
      c.drive = stroke.drive;
      cases.push_back(std::move(c));
    }
  }

  // The bust: 190 pushes around the top of the head (the model's +y extreme, a smooth convex
  // crown where "away from the centroid" is the outside); 20 in a quick run.
  CaseSpec bust;
  bust.group = "scan_190_pushes";
  bust.stroke = true;
  bust.outside = convex;
  const int pushes = options.quick ? 20 : 190;
  bust.name = std::filesystem::path(options.scan_path).filename().string() + " " + std::to_string(pushes) + " pushes " +
              describe(bust.settings);
  if (!std::filesystem::exists(options.scan_path)) {
    bust.skipped = options.scan_path + " not found (scripts/fetch_scans.sh)";
  } else {
    deform::PointModel scan = deform::read_model(options.scan_path);
    try {  // a scan with no length scale (every point at one place) is a problem of the file, named
      (void)deform::typical_spacing(scan, deform::PointIndex(scan));
    } catch (const std::invalid_argument& e) {
      throw deform::ModelFileError(options.scan_path, "", e.what());
    }
    deform::check_normals(scan, deform::NormalPolicy::kReestimate, options.scan_path);
    deform::ensure_normals(scan);  // the deformer needs normals; the oracle never reads them
    // This export is a hollow shell: an inner wall about 0.06 inside the outer one, wound
    // consistently toward the cavity (a ray from the centre crosses an inward-facing face, then
    // an outward-facing one, in every direction); turning every normal to one outside turns the
    // inner wall's. The pushes and the oracle take the bust as a solid, and a wall 1.5 spacings
    // thick is no solid for pushes up to 1.5 spacings deep: a finger past the outer wall stands
    // on the inner wall's outside. So the case keeps the outer wall alone, the surface the
    // thesis's bust had, and prints how many points it dropped. (Pushing inner-wall sites from
    // outside the outer wall, as this case once did, presses through both walls into the
    // cavity, and the PCA plane's 12 nearest points there mix the two walls.)
    const deform::PointModel as_read = scan;
    deform::orient_normals(scan);
    deform::PointModel outer;
    std::vector<std::size_t> kept;
    for (std::size_t i = 0; i < scan.size(); ++i) {
      if (dot(scan.normal(i), as_read.normal(i)) >= 0.0) kept.push_back(i);
    }
    outer.resize(kept.size(), /*with_normals=*/true, /*with_colors=*/false);
    for (std::size_t k = 0; k < kept.size(); ++k) {
      outer.set_position(k, scan.position(kept[k]));
      outer.set_normal(k, scan.normal(kept[k]));
    }
    if (kept.size() < scan.size()) {
      std::fprintf(stderr, "check: %s: the outer wall alone, %zu of %zu points (the shell's inner wall dropped)\n",
                   options.scan_path.c_str(), kept.size(), scan.size());
    }
    scan = std::move(outer);
    const std::size_t top = highest_along(scan, {0, 1, 0});
    const double reach = 0.04 * scan.bounding_box_diagonal();
    std::vector<std::size_t> sites;
    for (std::size_t i = 0; i < scan.size(); ++i) {
      if (norm(scan.position(i) - scan.position(top)) < reach) sites.push_back(i);
    }
    std::fprintf(stderr, "check: %s: %zu push sites (spacing %.3g)\n", options.scan_path.c_str(), sites.size(),
                 model_spacing(scan));
    bust.model = std::make_shared<const deform::PointModel>(std::move(scan));
    bust.drive = push_series(sites, pushes, 11);
    bust.invariants = !options.quick;
  }
  cases.push_back(std::move(bust));
  return cases;
}

}  // namespace sculpt::tools::check
