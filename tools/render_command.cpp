// sculpt render: a picture of a model, headless (OSMesa), as PNG. With --compare, the model
// beside its earlier version and coloured by how far each point moved; with --log, the probes
// and force arrows of a recorded session drawn over it; with --views, a row of views around it.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>
#include <stdexcept>
#include <vector>

#include "bad_normals_option.hpp"
#include "commands.hpp"
#include "number_check.hpp"
#include "output_files.hpp"
#include "output_paths.hpp"
#include "sculpt/deform/deformer.hpp"
#include "sculpt/deform/model_io.hpp"
#include "sculpt/render/picture.hpp"
#include "vector_argument.hpp"
#if SCULPT_HAS_LCM
#include "sculpt/logging/channels.hpp"
#include "sculpt/logging/event_log_reader.hpp"
#include "sculpt/logging/event_log_walk.hpp"
#include "sculpt/logging/records.hpp"
#endif

namespace sculpt::tools {
namespace {

constexpr int kMinEdge = 16;
constexpr int kMaxEdge = 4096;

// "WxH" with both in [kMinEdge, kMaxEdge].
bool parse_size(const std::string& text, int& width, int& height, std::string& error) {
  const std::size_t x = text.find_first_of("xX");
  auto number = [](std::string_view s, int& out) {
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
    return ec == std::errc() && end == s.data() + s.size() && !s.empty();
  };
  if (x == std::string::npos || !number(std::string_view(text).substr(0, x), width) ||
      !number(std::string_view(text).substr(x + 1), height)) {
    error = "'" + text + "' is not WIDTHxHEIGHT in pixels";
    return false;
  }
  if (width < kMinEdge || height < kMinEdge || width > kMaxEdge || height > kMaxEdge) {
    error =
        "each side must be " + std::to_string(kMinEdge) + " to " + std::to_string(kMaxEdge) + " pixels, got " + text;
    return false;
  }
  return true;
}

// The picture is written last, after seconds of rendering: a typo in its name or folder should
// cost nothing, so it is checked first.
// Folders still missing on its way are made when it is written, as every command's outputs.
void check_output_path(const std::string& path) {
  refuse_non_png_picture("--out", path);
  refuse_unwritable_output({"--out", path});
}

#if SCULPT_HAS_LCM
// One colour per finger (thumb .. little), strong enough to read on the clay and on the heat map.
constexpr std::array<render::Rgb, 5> kFingerColors{
    {{0.90, 0.20, 0.55}, {0.15, 0.45, 0.95}, {0.10, 0.70, 0.35}, {0.60, 0.30, 0.85}, {0.95, 0.55, 0.05}}};

render::Rgb finger_color(int finger) { return kFingerColors[static_cast<std::size_t>(finger) % kFingerColors.size()]; }

struct SessionOverlay {
  render::Overlay overlay;
  std::size_t collisions = 0;
  std::size_t fingertips = 0;
  std::size_t skipped = 0;
};

// The session as pictures: each fingertip's path in the model frame, and for each collision its
// probe (a dot) and the force F = P_f - A as an arrow from the contact point A toward the probe,
// `arrow_scale` times its length (a press of a few percent of the model is hard to see at 1).
//
// The camera is fitted to everything drawn, so a position no session logs (finite, but 1e300
// from the model) would shrink the model to nothing or leave no finite frame at all. What lies
// beyond the station's own probe range (deform::GuardSettings::probe_range diagonals from the
// model's centre; the station drops fingertips beyond it) is not drawn, counted, and named by
// its first byte offset.
SessionOverlay read_session_overlay(const std::string& path, double arrow_scale, const deform::PointModel& model) {
  SessionOverlay session;
  std::map<std::pair<int, int>, render::Polyline> paths;  // by (hand, finger)
  const auto skip = [&](std::uint64_t, const std::string& what) {
    std::fprintf(stderr, "skipped  %s\n", what.c_str());
    ++session.skipped;
  };
  const render::Vec3 centre = model.bounding_box_centre();
  const double diagonals = deform::GuardSettings{}.probe_range;  // the station's own bound on a probe
  const double range = diagonals * std::max(model.bounding_box_diagonal(), 1e-30);
  const auto near_model = [&](const render::Vec3& p) { return deform::is_finite(p) && norm(p - centre) <= range; };
  std::size_t far = 0;
  std::uint64_t first_far = 0;
  const auto skip_far = [&](std::uint64_t offset) {
    if (far++ == 0) first_far = offset;
  };
  std::size_t sculpt_events = 0;
  const auto take = [&](const logging::LogEvent& event) {
    std::string error;
    if (event.channel.rfind("SCULPT_", 0) == 0) ++sculpt_events;
    if (event.channel == logging::kFingertipChannel) {
      sculpt_lcm::fingertip_state_t tip;
      if (!logging::decode(event, tip, error)) {
        skip(event.offset, error);
        return;
      }
      const render::Vec3 p{tip.registered[0], tip.registered[1], tip.registered[2]};
      if (!near_model(p)) {
        skip_far(event.offset);
        return;
      }
      render::Polyline& line = paths[{tip.hand, tip.finger}];
      if (line.points.empty()) {
        const render::Rgb c = finger_color(tip.finger);
        line.color = {0.5 + 0.5 * c.r, 0.5 + 0.5 * c.g, 0.5 + 0.5 * c.b};  // paler than its probes
      }
      line.points.push_back(p);
      ++session.fingertips;
    } else if (event.channel == logging::kCollisionChannel) {
      sculpt_lcm::collision_event_t message;
      logging::CollisionRecord c;
      if (!logging::decode(event, message, error) || !logging::from_lcm(message, c)) {
        skip(event.offset, error.empty() ? path + ": byte offset " + std::to_string(event.offset) +
                                               ": SCULPT_COLLISION event with invalid fields"
                                         : error);
        return;
      }
      const render::Vec3 contact{c.contact[0], c.contact[1], c.contact[2]};
      const render::Vec3 tip = contact + arrow_scale * render::Vec3{c.force[0], c.force[1], c.force[2]};
      const render::Vec3 probe{c.probe[0], c.probe[1], c.probe[2]};
      if (!near_model(contact) || !near_model(tip) || !near_model(probe)) {
        skip_far(event.offset);
        return;
      }
      const render::Rgb color = finger_color(c.finger);
      session.overlay.arrows.push_back({contact, tip, color});
      session.overlay.markers.push_back({probe, color, 7.0});
      ++session.collisions;
    }
  };
  const logging::EventLogTotals totals = logging::for_each_event(path, take, skip);
  // An empty file, random bytes or another program's log drew the bare model with exit 0.
  if (totals.file_size == 0) throw std::runtime_error(path + ": empty file, not an event log");
  if (sculpt_events == 0) {
    throw std::runtime_error(path + ": not a glovesculpt log: no event on a SCULPT_ channel in its " +
                             std::to_string(totals.file_size) + " bytes");
  }
  if (far > 0) {
    std::fprintf(stderr,
                 "skipped  %s: %zu events hold a position beyond %.4g model units of the model's centre (%g "
                 "diagonals, the station's probe range), the first at byte offset %llu: not drawn\n",
                 path.c_str(), far, range, diagonals, static_cast<unsigned long long>(first_far));
    session.skipped += far;
  }
  for (auto& [finger, line] : paths) session.overlay.paths.push_back(std::move(line));
  return session;
}
#endif

class RenderCommand final : public Command {
 public:
  explicit RenderCommand(CLI::App& app) {
    sub_ = app.add_subcommand("render", "Draw a model to a PNG picture, headless (OSMesa)");
    sub_->add_option("model", model_path_, "Model to draw (.ply, .off or .xyz)")->required();
    sub_->add_option("--out", out_path_, "Write the picture here (.png)")->required();
    sub_->add_option("--compare", before_path_,
                     "Earlier version of the model (same points): draw both, the model coloured by displacement");
    auto* log =
        sub_->add_option("--log", log_path_, "Event log of a session (sculpt run): draw its probes and force arrows");
    // Options that only shape something another option asks for are refused without it.
    sub_->add_option("--arrow-scale", arrow_scale_, "With --log: draw each force arrow this many times its length")
        ->check(finite_in(0.0, true, 1e6, false))
        ->default_val(1.0)
        ->needs(log);
    sub_->add_option("--views", views_, "A row of this many views around the model")->check(CLI::Range(1, 36));
    auto* azimuth = sub_->add_option("--azimuth", request_.azimuth_deg, "Degrees about the up axis, 0 = front")
                        ->check(finite_in(-360.0, false, 360.0, false, "degrees"))
                        ->default_val(30.0);
    auto* elevation = sub_->add_option("--elevation", request_.elevation_deg, "Degrees above the horizon")
                          ->check(finite_in(-90.0, false, 90.0, false, "degrees"))
                          ->default_val(20.0);
    view_option_ =
        sub_->add_option("--view", view_text_, "DX,DY,DZ: look along this direction (instead of the angles)");
    view_option_->excludes(azimuth)->excludes(elevation);
    sub_->add_option("--up", up_, "The model's up axis: x | y | z")
        ->check(CLI::IsMember({"x", "y", "z"}))
        ->default_val("y");
    sub_->add_option("--size", size_text_, "WxH of each view, in pixels")->default_val("800x600");
    bad_normals_.add_to(*sub_);
  }

  bool chosen() const override { return sub_->parsed(); }

  int run() override {
    try {
      std::string error;
      if (!parse_size(size_text_, request_.view_width, request_.view_height, error)) {
        throw std::invalid_argument("--size: " + error);
      }
      if (view_option_->count()) {
        request_.look = parse_vec3(view_text_, error);
        if (!request_.look) throw std::invalid_argument("--view: " + error);
        // Only the direction counts: scaled by its largest component, so that 1e155 does not
        // overflow the length (the picture came out empty) nor 1e-170 underflow it to zero.
        deform::Vec3& look = *request_.look;
        const double largest = std::max({std::abs(look.x), std::abs(look.y), std::abs(look.z)});
        if (!(largest > 0.0)) throw std::invalid_argument("--view: the direction is zero");
        look = {look.x / largest, look.y / largest, look.z / largest};
      }
      request_.views = views_;
      request_.up = up_ == "x" ? render::UpAxis::kX : up_ == "z" ? render::UpAxis::kZ : render::UpAxis::kY;
      try {
        render::check_picture_request(request_, !before_path_.empty());
      } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(std::string("--views and --size: ") + e.what());
      }
      check_output_path(out_path_);
      refuse_output_naming_input({"--out", out_path_}, std::vector<NamedPath>{{"the model", model_path_},
                                                                              {"--compare", before_path_},
                                                                              {"the log (--log)", log_path_}});
#if !SCULPT_HAS_LCM
      if (!log_path_.empty()) {
        std::cerr << "sculpt render: error: --log needs LCM; reconfigure with -DSCULPT_WITH_LCM=ON\n";
        return kExitUsage;
      }
#endif
    } catch (const std::invalid_argument& e) {
      std::cerr << "sculpt render: error: " << e.what() << "\n";
      return kExitUsage;
    }

    try {
      return render();
    } catch (const std::exception& e) {  // unreadable input, nothing to draw, no OpenGL context, unwritable picture
      std::cerr << "sculpt render: error: " << e.what() << "\n";
      return kExitFailure;
    }
  }

 private:
  int render() {
    const auto start = std::chrono::steady_clock::now();
    const deform::PointModel model = read_and_check(model_path_);
    std::optional<deform::PointModel> before;
    if (!before_path_.empty()) {
      before = read_and_check(before_path_);
      // Two readable files that do not belong together: the arguments are wrong, not the files.
      if (before->size() != model.size()) {
        std::cerr << "sculpt render: error: --compare " << before_path_ << " has " << before->size() << " points and "
                  << model_path_ << " " << model.size()
                  << "; the heat map pairs points by index, so both must be versions of one model\n";
        return kExitUsage;
      }
    }
#if SCULPT_HAS_LCM
    if (!log_path_.empty()) {
      SessionOverlay session = read_session_overlay(log_path_, arrow_scale_, model);
      std::printf("log      %s: %zu collision events, %zu fingertip states%s\n", log_path_.c_str(), session.collisions,
                  session.fingertips,
                  session.skipped ? (", " + std::to_string(session.skipped) + " skipped").c_str() : "");
      request_.overlay = std::move(session.overlay);
    }
#endif
    render::PictureInfo info;
    const render::Image picture = render::render_picture(model, before ? &*before : nullptr, request_, &info);
    write_picture_output(out_path_, picture);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    const char* drawn = !model.triangles.empty()               ? "drawn as faces"
                        : before && !before->triangles.empty() ? "drawn with the faces of --compare's model"
                                                               : "drawn as splats";
    std::printf("model    %s: %zu points, %s\n", model_path_.c_str(), model.size(), drawn);
    if (before)
      std::printf("compare  %s: largest displacement %.4g model units\n", before_path_.c_str(), info.max_displacement);
    std::printf("wrote    %s: %dx%d (%d x %d views), %.4g ms\n", out_path_.c_str(), picture.width, picture.height,
                info.rows, info.columns, ms);
    return kExitOk;
  }

  // A model with no points, or whose points all coincide, has nothing to draw: the fault is
  // the file's, so it is reported as the file's (exit 1), not as an argument. Zero or NaN normals
  // are re-estimated (or refused) as deform and replay do: lit by them, a model drew as one dark
  // disc, with no word why.
  deform::PointModel read_and_check(const std::string& path) const {
    deform::PointModel model = deform::read_model(path);
    if (model.empty()) throw deform::ModelFileError(path, "", "the model has no points to draw");
    if (!(model.bounding_box_diagonal() > 0.0)) {
      const std::string what = model.size() == 1
                                   ? "the model has a single point"
                                   : "the model's " + std::to_string(model.size()) + " points all coincide";
      throw deform::ModelFileError(path, "", what + ": no size to draw (a splat's is its spacing)");
    }
    bad_normals_.check(model, path);
    return model;
  }

  CLI::App* sub_ = nullptr;
  CLI::Option* view_option_ = nullptr;
  std::string model_path_, out_path_, before_path_, log_path_, view_text_, up_, size_text_;
  int views_ = 1;
  double arrow_scale_ = 1.0;
  render::PictureRequest request_;
  BadNormalsOption bad_normals_;
};

}  // namespace

std::unique_ptr<Command> add_render_command(CLI::App& app) { return std::make_unique<RenderCommand>(app); }

}  // namespace sculpt::tools
