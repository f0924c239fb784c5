// sculpt deform: one collision frame on a model file, for scripting and checks. Every contact of
// one invocation is one frame, solved jointly (MATH.md §3-4).
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <cstring>
#include <iostream>
#include <stdexcept>
#include <vector>

#include "bad_normals_option.hpp"
#include "commands.hpp"
#include "guard_report.hpp"
#include "json_report.hpp"
#include "output_files.hpp"
#include "output_paths.hpp"
#include "repeat_timing.hpp"
#include "sculpt/deform/deformer.hpp"
#include "sculpt/deform/inverse_sqrt.hpp"
#include "sculpt/deform/model_io.hpp"
#include "sculpt/deform/model_scale.hpp"
#include "sculpt/deform/normals.hpp"
#include "sculpt/deform/settings_range.hpp"
#include "vector_argument.hpp"

namespace sculpt::tools {
namespace {

using deform::Vec3;
using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

nlohmann::json to_json(const Vec3& v) { return {v.x, v.y, v.z}; }

const char* state_name(deform::ProbeState s) {
  switch (s) {
    case deform::ProbeState::kFree: return "free";
    case deform::ProbeState::kGuarded: return "guarded";
    case deform::ProbeState::kCollided: return "collided";
    case deform::ProbeState::kStartedInside: return "started_inside";
    case deform::ProbeState::kDropped: return "dropped";
  }
  return "?";
}

const char* rule_name(deform::SourceRule r) {
  switch (r) {
    case deform::SourceRule::kPrevious: return "previous";
    case deform::SourceRule::kEarlier: return "earlier";
    case deform::SourceRule::kPushedBack: return "pushed_back";
    case deform::SourceRule::kCleared: return "cleared";
  }
  return "?";
}

std::string format(const Vec3& v) {
  char buffer[96];
  std::snprintf(buffer, sizeof buffer, "(%.6g, %.6g, %.6g)", v.x, v.y, v.z);
  return buffer;
}

class DeformCommand final : public Command {
 public:
  explicit DeformCommand(CLI::App& app) {
    sub_ = app.add_subcommand("deform", "Apply one collision frame of fingertip contacts to a model file");
    sub_->add_option("--model", model_path_, "Input model (.ply, .off or .xyz)")->required();
    sub_->add_option("--out", out_path_,
                     "Write the deformed model here (.ply, .off or .xyz; faces kept in .ply and .off)");
    sub_->add_option("--contact", contacts_,
                     "X0,Y0,Z0:X1,Y1,Z1 probe before (outside) and after (pressed in); one per finger")
        ->required()
        ->take_all();
    sub_->add_option("--G", material_.shear_modulus, "Shear modulus G")->default_val(3e7);
    sub_->add_option("--nu", material_.poisson_ratio, "Poisson's ratio nu, in (-1, 0.5]")->default_val(0.45);
    sub_->add_option("--kernel", kernel_, "kelvin | regularized")
        ->check(CLI::IsMember({"kelvin", "regularized"}))
        ->default_val("kelvin");
    eps_reg_option_ =
        sub_->add_option("--eps-reg", eps_reg_, "Regularization radius of the regularized kernel (model units)");
    sub_->add_option("--form", form_, "force (thesis ch. 3: weights are the force) | scale (ch. 4: weights scale F)")
        ->check(CLI::IsMember({"force", "scale"}))
        ->default_val("force");
    sub_->add_option("--mode", mode_, "push | pull | auto (pull when every contact starts inside)")
        ->check(CLI::IsMember({"push", "pull", "auto"}))
        ->default_val("auto");
    bc_option_ =
        sub_->add_option("--bc-radius", bc_radius_, "eps: points this close to A follow the probe [typical spacing]");
    dd_option_ = sub_->add_option("--delta-d", delta_d_, "Δd: least source distance from A [0.25 x typical spacing]");
    dr_option_ = sub_->add_option("--delta-r", delta_r_,
                                  "Δr: a free finger this close pins its surface [1.5 x typical spacing]");
    region_option_ =
        sub_->add_option("--region", region_radius_, "Move only points within this radius of a contact (default: all)");
    // The band exists only around a region: without --region the weight would go unused.
    sub_->add_option("--border-weight", border_weight_, "With --region: weight of its pinned band against a contact")
        ->default_val(1.0)
        ->needs(region_option_);
    sub_->add_flag("--strict-region", strict_region_,
                   "With --region: move only its points even where it holds so much of the model that the global "
                   "frame would cost less (by default such a frame moves every point)")
        ->needs(region_option_);
    reference_option_ = sub_->add_option("--reference", reference_text_,
                                         "X,Y,Z point known to be outside (for models without normals)");
    CLI::Option* double_flag =
        sub_->add_flag("--double", use_double_, "Evaluate the per-point loop in double instead of float");
    sub_->add_flag("--fast-inverse-sqrt", fast_inverse_sqrt_,
                   "An approximation (float only): 1/r from the processor's reciprocal square root estimate and one "
                   "Newton step (relative error below 2^-21) instead of a square root and a division")
        ->excludes(double_flag);
    sub_->add_option("--threads", threads_, "2: a worker on a second core takes half of a large displacement pass")
        ->check(CLI::Range(1, 2))
        ->default_val(1);
    sub_->add_option("--normal-skip-bound", normal_skip_bound_,
                     "The bounded normal update (an approximation, 0 = off): points whose gradient bound is at "
                     "most this keep their normal, within asin(b / (1 - b)) of the carried one")
        ->check(CLI::Range(0.0, deform::kMaxNormalSkipBound))
        ->default_val(0.0);
    encoding_option_ = sub_->add_option("--encoding", encoding_, "ascii | binary | binary_big_endian for a .ply output")
                           ->check(CLI::IsMember({"ascii", "binary", "binary_big_endian"}))
                           ->default_val("binary");
    sub_->add_option("--json", json_path_, "Also write the report as JSON here ('-' for stdout)");
    sub_->add_option("--repeat", repeat_,
                     "Run the frame this many times from the same starting model; time_ms gets frame_median "
                     "and frame_p99 beside the first, cold frame, and every run must give the same bytes")
        ->check(CLI::Range(1, kMaxRepeat))
        ->default_val(1);
    bad_normals_.add_to(*sub_);
  }

  bool chosen() const override { return sub_->parsed(); }

  int run() override {
    if (json_path_ == "-") reserve_stdout_for_json();
    deform::DeformSettings settings;
    std::vector<deform::ProbeMotion> probes;
    std::optional<Vec3> reference;
    // Everything about the arguments is checked before the model is read: a typo costs nothing.
    try {
      for (const std::string& text : contacts_) {
        std::string error;
        auto probe = parse_contact(text, error);
        if (!probe) throw std::invalid_argument(contact_name(probes.size()) + ": " + error);
        probes.push_back(*probe);
      }
      if (probes.size() > deform::kMaxSources) {
        throw std::invalid_argument("--contact: at most " + std::to_string(deform::kMaxSources) +
                                    " contacts in one frame, got " + std::to_string(probes.size()));
      }
      if (reference_option_->count()) {
        std::string error;
        reference = parse_vec3(reference_text_, error);
        if (!reference) throw std::invalid_argument("--reference: " + error);
      }
      settings.kernel.material = material_;
      settings.kernel.kind = kernel_ == "kelvin" ? deform::KernelKind::kKelvin : deform::KernelKind::kRegularized;
      if (settings.kernel.kind == deform::KernelKind::kRegularized && !eps_reg_option_->count()) {
        throw std::invalid_argument("--kernel regularized needs --eps-reg");
      }
      if (settings.kernel.kind == deform::KernelKind::kKelvin && eps_reg_option_->count()) {
        throw std::invalid_argument("--eps-reg applies only to --kernel regularized");
      }
      settings.kernel.regularization = eps_reg_;
      settings.kernel.validate();
      auto positive = [](CLI::Option* o, double v, const char* name) {
        if (o->count() && !(v > 0.0 && std::isfinite(v))) {
          throw std::invalid_argument(std::string(name) + " must be a positive number");
        }
      };
      positive(bc_option_, bc_radius_, "--bc-radius");
      positive(dd_option_, delta_d_, "--delta-d");
      positive(region_option_, region_radius_, "--region");
      if (dr_option_->count() && !(delta_r_ >= 0.0)) throw std::invalid_argument("--delta-r must be >= 0");
      // .off and .xyz have one encoding each: a PLY encoding asked for them would be ignored.
      if (encoding_option_->count() && lower_extension(out_path_) != ".ply") {
        throw std::invalid_argument("--encoding applies only to a .ply --out" +
                                    (out_path_.empty() ? std::string(" (no --out given)") : ", not " + out_path_));
      }
      if (!(border_weight_ >= 0.0)) throw std::invalid_argument("--border-weight must be >= 0");
      // --out may replace the model (an edit in place, written atomically); the JSON may not.
      refuse_output_naming_input({"--json", json_path_}, std::vector<NamedPath>{{"the model (--model)", model_path_}});
      const std::vector<NamedPath> outputs = {{"--out", out_path_}, {"--json", json_path_}};
      refuse_shared_outputs(outputs);
      for (const NamedPath& output : outputs) refuse_unwritable_output(output);
      if (!out_path_.empty()) refuse_unwritable_model_format("--out", out_path_);
    } catch (const std::invalid_argument& e) {
      std::cerr << "sculpt deform: error: " << e.what() << "\n";
      return kExitUsage;
    }

    try {
      return deform_model(settings, probes, reference);
    } catch (const deform::ModelFileError& e) {
      std::cerr << "sculpt deform: error: " << e.what() << "\n";
      return kExitFailure;
    } catch (const std::invalid_argument& e) {  // settings that do not fit this model
      std::cerr << "sculpt deform: error: " << e.what() << "\n";
      return kExitUsage;
    } catch (const std::exception& e) {
      std::cerr << "sculpt deform: error: " << e.what() << "\n";
      return kExitFailure;
    }
  }

 private:
  int deform_model(deform::DeformSettings settings, std::vector<deform::ProbeMotion>& probes,
                   const std::optional<Vec3>& reference) {
    const auto load_start = Clock::now();
    deform::PointModel model = deform::read_model(model_path_);
    const deform::NormalReport normal_report = bad_normals_.check(model, model_path_);
    const double load_ms = ms_since(load_start);
    // The length scale first: without one (all points coincide) nothing below means anything,
    // and the fault is the file's, so it is reported as the file's.
    const deform::TypicalSpacing spacing = file_spacing(model);
    // The reference point stands in for missing normals (thesis 3.2): with the file's normals it
    // would be ignored.
    if (reference && model.has_normals()) {
      throw std::invalid_argument("--reference is not used: " + model_path_ +
                                  " has normals, and a reference point only replaces missing ones");
    }
    std::string normals_source = model.has_normals() ? "file" : "none";
    if (!model.has_normals() && !reference) {
      normals_source = model.triangles.empty() ? "estimated (PCA)" : "from faces";
      deform::ensure_normals(model);
    }

    const auto setup_start = Clock::now();
    deform::ContactSettings& contact = settings.contact;
    contact.bc_radius = bc_option_->count() ? bc_radius_ : spacing.value;
    contact.min_source_distance = dd_option_->count() ? delta_d_ : 0.25 * spacing.value;
    contact.guard_distance = dr_option_->count() ? delta_r_ : 1.5 * spacing.value;
    contact.reference = reference;
    settings.solver.form = form_ == "force" ? deform::WeightForm::kForce : deform::WeightForm::kScale;
    settings.field.precision = use_double_ ? deform::Precision::kDouble : deform::Precision::kFloat;
    settings.threads = threads_;
    settings.field.normal_skip_bound = normal_skip_bound_;
    settings.field.fast_inverse_sqrt = fast_inverse_sqrt_;
    if (region_option_->count()) {
      settings.region.kind = deform::RegionSettings::Kind::kRadius;
      settings.region.radius = region_radius_;
    }
    settings.region.border_weight = border_weight_;
    settings.region.global_when_cheaper = !strict_region_;
    settings.traction = model.has_normals();
    check_against_model(settings, probes, model);
    contact.mode = choose_mode(model, probes, contact);
    deform::Deformer deformer(model, settings);
    const double setup_ms = ms_since(setup_start);

    // The starting model and the first result are kept only when the frame is repeated: each
    // repeat restores the start (the deformer's own undo, so the index needs no rebuild) and must
    // reproduce the first result bit for bit.
    const deform::PointModel start = repeat_ > 1 ? model : deform::PointModel{};
    std::vector<double> times_ms;
    times_ms.reserve(static_cast<std::size_t>(repeat_));
    const auto frame_start = Clock::now();
    const deform::FrameReport* report = &deformer.deform(probes);
    times_ms.push_back(ms_since(frame_start));
    const deform::PointModel first = repeat_ > 1 ? model : deform::PointModel{};
    for (int run = 1; run < repeat_; ++run) {
      deformer.restore(start);
      const auto repeat_start = Clock::now();
      report = &deformer.deform(probes);
      times_ms.push_back(ms_since(repeat_start));
      if (!same_result(model, first)) {
        throw std::runtime_error("run " + std::to_string(run + 1) + " of --repeat " + std::to_string(repeat_) +
                                 " moved the points differently from the first: the frame is not deterministic");
      }
    }
    const RepeatTimes times = summarise_repeats(times_ms);
    const double frame_ms = times.cold_ms;

    double write_ms = 0.0;
    if (!out_path_.empty()) {
      const auto write_start = Clock::now();
      const auto encoding = encoding_ == "ascii"    ? deform::PlyEncoding::kAscii
                            : encoding_ == "binary" ? deform::PlyEncoding::kBinaryLittleEndian
                                                    : deform::PlyEncoding::kBinaryBigEndian;
      write_model_output(out_path_, model, encoding);
      write_ms = ms_since(write_start);
    }

    nlohmann::json json = make_json(model, settings, normals_source, spacing, *report, deformer.frames().size());
    json["time_ms"] = {{"load", load_ms}, {"setup", setup_ms}, {"frame", frame_ms}, {"write", write_ms}};
    if (repeat_ > 1) {
      json["time_ms"]["frame_median"] = times.median_ms;
      json["time_ms"]["frame_p99"] = times.p99_ms;
      json["repeat"] = repeat_;
    }
    json["normals_checked"] = bad_normals_.to_json(normal_report);
    json["faces"] = model.triangles.size() / 3;
    print_summary(model, settings, normals_source, spacing, *report, frame_ms);
    if (repeat_ > 1) {
      std::printf("repeat   %d runs, the same result each time: frame median %.4g ms, p99 %.4g ms (first %.4g ms)\n",
                  repeat_, times.median_ms, times.p99_ms, frame_ms);
    }
    stamp_summary(json);
    if (!json_path_.empty()) write_json(json_path_, json);
    return kExitOk;
  }

  deform::TypicalSpacing file_spacing(const deform::PointModel& model) const {
    try {
      return deform::typical_spacing(model, deform::PointIndex(model));
    } catch (const std::invalid_argument& e) {
      throw deform::ModelFileError(model_path_, "", e.what());
    }
  }

  // Settings and probes far outside the model's size are typos or hostile input; their squares
  // would leave float's range next to the model's coordinates.
  static void check_against_model(const deform::DeformSettings& settings,
                                  const std::vector<deform::ProbeMotion>& probes, const deform::PointModel& model) {
    deform::SettingNames names;
    names.bc_radius = "--bc-radius";
    names.min_source_distance = "--delta-d";
    names.guard_distance = "--delta-r";
    names.region_radius = "--region";
    names.regularization = "--eps-reg";
    deform::check_settings_against_model(settings, model, names);
    const deform::ModelExtent extent = deform::ModelExtent::of(model);
    for (std::size_t i = 0; i < probes.size(); ++i) {
      deform::check_position_against_model(contact_name(i) + " (before)", probes[i].previous, extent);
      deform::check_position_against_model(contact_name(i) + " (after)", probes[i].current, extent);
    }
  }

  static std::string contact_name(std::size_t index) { return "--contact " + std::to_string(index); }

  deform::ContactMode choose_mode(const deform::PointModel& model, const std::vector<deform::ProbeMotion>& probes,
                                  const deform::ContactSettings& contact) const {
    if (mode_ == "push") return deform::ContactMode::kPush;
    if (mode_ == "pull") return deform::ContactMode::kPull;
    const deform::PointIndex index(model);
    for (const deform::ProbeMotion& p : probes) {
      if (deform::locate(model, index, 0.0, p.previous, contact).side >= 0.0) return deform::ContactMode::kPush;
    }
    return deform::ContactMode::kPull;
  }

  nlohmann::json make_json(const deform::PointModel& model, const deform::DeformSettings& s,
                           const std::string& normals_source, const deform::TypicalSpacing& spacing,
                           const deform::FrameReport& r, std::size_t frames_applied) const {
    using nlohmann::json;
    json solve = {{"ok", r.solve.ok},
                  {"rows", r.solve.rows},
                  {"unknowns", r.solve.unknowns},
                  {"rank", r.solve.rank},
                  {"residual", r.solve.residual},
                  {"relative_residual", r.solve.relative_residual},
                  // JSON has no infinity: a rank-deficient solve is null beside a flag.
                  {"condition", std::isfinite(r.solve.condition) ? json(r.solve.condition) : json(nullptr)},
                  {"rank_deficient", !std::isfinite(r.solve.condition)},
                  {"effective_condition", r.solve.effective_condition},
                  {"damped", r.solve.damped}};
    json contacts = json::array();
    for (std::size_t i = 0; i < contacts_.size(); ++i) {
      const deform::ContactReport& c = r.contacts[i];
      const bool collided = c.state == deform::ProbeState::kCollided;
      json entry = {{"contact", i},
                    {"collided", collided},
                    {"state", state_name(c.state)},
                    {"nearest_index", c.nearest},
                    {"nearest_point", to_json(c.contact)},
                    {"distance", c.distance},
                    {"side_after", c.side_after},
                    {"miss", c.miss},
                    {"pushed_out", c.pushed_out},
                    {"probe_after", to_json(c.probe_after)}};
      if (collided) {
        entry["source"] = to_json(c.source);
        entry["source_rule"] = rule_name(c.source_rule);
        entry["force"] = to_json(c.force);
        entry["weights"] = to_json(c.weights);
        entry["effective_force"] = to_json(c.effective_force);
        entry["boundary_points"] = c.boundary_points;
        entry["residual"] = r.solve.residual;
        entry["relative_residual"] = r.solve.relative_residual;
        entry["condition"] = solve["condition"];
        entry["rank_deficient"] = solve["rank_deficient"];
        if (c.has_traction) {
          entry["traction"] = to_json(c.traction);
          entry["traction_resultant"] = to_json(c.traction_resultant);
        }
      }
      contacts.push_back(entry);
    }
    const auto& k = s.kernel;
    return {{"model", model_path_},
            {"points", model.size()},
            {"normals", normals_source},
            {"out", out_path_.empty() ? json(nullptr) : json(out_path_)},
            {"kernel", k.kind == deform::KernelKind::kKelvin ? "kelvin" : "regularized"},
            {"eps_reg", k.regularization},
            {"material",
             {{"G", k.material.shear_modulus}, {"nu", k.material.poisson_ratio}, {"E", k.material.young_modulus()}}},
            {"form", form_},
            {"mode", s.contact.mode == deform::ContactMode::kPush ? "push" : "pull"},
            {"precision", use_double_ ? "double" : "float"},
            {"spacing", spacing.value},
            {"spacing_statistic", spacing.statistic},
            {"bc_radius", s.contact.bc_radius},
            {"delta_d", s.contact.min_source_distance},
            {"delta_r", s.contact.guard_distance},
            {"region", s.region.kind == deform::RegionSettings::Kind::kRadius ? json(s.region.radius) : json("global")},
            {"collisions", r.collisions},
            {"contacts", contacts},
            {"solve", solve},
            {"points_moved", r.region_points},
            {"global_frame", r.global},
            {"border_points", r.border_points},
            {"displacement_conditions", r.displacement_conditions},
            {"max_displacement", r.max_displacement},
            {"max_contact_displacement", r.max_contact_displacement},
            {"max_border_displacement", r.max_border_displacement},
            {"frames_applied", frames_applied},
            {"rejected", r.rejected},
            {"min_jacobian", r.min_jacobian},
            {"normal_skip_bound", s.field.normal_skip_bound},
            {"fast_inverse_sqrt", s.field.fast_inverse_sqrt},
            {"normals_bounded", r.normals_bounded},
            {"max_normal_bound_angle", r.max_normal_bound_angle},
            {"max_miss", r.max_miss},
            {"guards", guards_json(r.guards)}};
  }

  void print_summary(const deform::PointModel& model, const deform::DeformSettings& s,
                     const std::string& normals_source, const deform::TypicalSpacing& spacing,
                     const deform::FrameReport& r, double frame_ms) const {
    std::printf("model    %s: %zu points, normals %s, spacing %.4g (%s)\n", model_path_.c_str(), model.size(),
                normals_source.c_str(), spacing.value, spacing.statistic.c_str());
    char region[32] = "global";
    if (region_option_->count()) std::snprintf(region, sizeof region, "%.4g", region_radius_);
    std::printf("settings %s kernel, G %.4g, nu %.4g, %s form, %s, eps %.4g, delta_d %.4g, delta_r %.4g, region %s\n",
                kernel_.c_str(), s.kernel.material.shear_modulus, s.kernel.material.poisson_ratio, form_.c_str(),
                s.contact.mode == deform::ContactMode::kPush ? "push" : "pull", s.contact.bc_radius,
                s.contact.min_source_distance, s.contact.guard_distance, region);
    for (std::size_t i = 0; i < contacts_.size(); ++i) {
      const deform::ContactReport& c = r.contacts[i];
      std::printf("contact  %zu: %s, nearest #%u %s at %.4g", i, state_name(c.state), c.nearest,
                  format(c.contact).c_str(), c.distance);
      if (c.state == deform::ProbeState::kCollided) {
        std::printf(", source %s (%s), F %s, effective force %s, %zu bc points", format(c.source).c_str(),
                    rule_name(c.source_rule), format(c.force).c_str(), format(c.effective_force).c_str(),
                    c.boundary_points);
      }
      if (c.pushed_out) std::printf(", pushed out to %s", format(c.probe_after).c_str());
      std::printf("\n");
    }
    if (r.collisions > 0) {
      std::printf(
          "solve    %zu rows x %zu unknowns, rank %zu, residual %.3g (relative %.3g), condition %.3g "
          "(%.3g over the kept rank)%s\n",
          r.solve.rows, r.solve.unknowns, r.solve.rank, r.solve.residual, r.solve.relative_residual, r.solve.condition,
          r.solve.effective_condition, r.solve.damped ? ", damped" : "");
    }
    std::printf(
        "result   %zu collision(s), %zu points moved, max displacement %.4g, band/contact %.3g, frame %.3g ms\n",
        r.collisions, r.region_points, r.max_displacement,
        r.max_contact_displacement > 0 ? r.max_border_displacement / r.max_contact_displacement : 0.0, frame_ms);
    if (s.field.normal_skip_bound > 0.0) {
      std::printf("normals  %zu kept under the bound %g (each within %.3g rad of the carried one)\n", r.normals_bounded,
                  s.field.normal_skip_bound, r.max_normal_bound_angle);
    }
    if (s.field.fast_inverse_sqrt) {
      std::printf("1/r      %s estimate and one Newton step (relative error below 2^-21)\n",
                  deform::inverse_sqrt_estimate_kind());
    }
    std::printf("guards   min det(I + grad u) %.4g, miss %.4g%s;", r.min_jacobian, r.max_miss,
                r.rejected ? ", frame undone" : "");
    const std::string guards = acted_guards(r.guards, ' ');
    std::printf("%s\n", guards.empty() ? " none acted" : guards.c_str());
    if (!out_path_.empty()) std::printf("wrote    %s\n", out_path_.c_str());
  }

  // Byte for byte (a -0 against a 0, or two NaNs, would compare wrongly as floats).
  static bool same_result(const deform::PointModel& a, const deform::PointModel& b) {
    auto same = [](const std::vector<float>& u, const std::vector<float>& v) {
      return u.size() == v.size() && (u.empty() || std::memcmp(u.data(), v.data(), u.size() * sizeof(float)) == 0);
    };
    return same(a.x, b.x) && same(a.y, b.y) && same(a.z, b.z) && same(a.nx, b.nx) && same(a.ny, b.ny) &&
           same(a.nz, b.nz);
  }

  static constexpr int kMaxRepeat = 1000000;
  CLI::App* sub_ = nullptr;
  int repeat_ = 1;
  int threads_ = 1;
  double normal_skip_bound_ = 0.0;
  bool fast_inverse_sqrt_ = false;
  std::string model_path_, out_path_, json_path_, kernel_, form_, mode_, reference_text_, encoding_;
  std::vector<std::string> contacts_;
  deform::Material material_;
  double eps_reg_ = 0.0, bc_radius_ = 0.0, delta_d_ = 0.0, delta_r_ = 0.0, region_radius_ = 0.0;
  double border_weight_ = 1.0;
  bool use_double_ = false;
  bool strict_region_ = false;
  BadNormalsOption bad_normals_;
  CLI::Option *eps_reg_option_ = nullptr, *bc_option_ = nullptr, *dd_option_ = nullptr, *dr_option_ = nullptr,
              *region_option_ = nullptr, *reference_option_ = nullptr, *encoding_option_ = nullptr;
};

}  // namespace

std::unique_ptr<Command> add_deform_command(CLI::App& app) { return std::make_unique<DeformCommand>(app); }

}  // namespace sculpt::tools
