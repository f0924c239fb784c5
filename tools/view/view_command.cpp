// sculpt view: a window that follows the station. It loads the scene's base model as sculpt run
// does and re-applies every collision frame it receives on SCULPT_COLLISION to its own copy (the
// log is the edit history), or plays a recorded session (--log). Pictures are rendered by OSMesa
// and copied into an X window (see image_window.hpp for why), at most --fps a second, from a
// niced process with one llvmpipe thread, so that the station keeps its cores.
#include <CLI/CLI.hpp>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <variant>
#include <vector>

#include "catch_up_log.hpp"
#include "commands.hpp"
#include "frame_follower.hpp"
#include "lcm_url_option.hpp"
#include "image_window.hpp"
#include "lcm_receiver.hpp"
#include "number_check.hpp"
#include "orbit_view.hpp"
#include "output_files.hpp"
#include "output_paths.hpp"
#include "playback.hpp"
#include "sculpt/base/clock.hpp"
#include "sculpt/base/regular_file.hpp"
#include "sculpt/deform/model_io.hpp"
#include "sculpt/logging/frame_runs.hpp"
#include "sculpt/render/camera.hpp"
#include "sculpt/render/render_model.hpp"
#include "sculpt/render/text.hpp"
#include "sculpt/render/view_renderer.hpp"
#include "sculpt/rt/scene.hpp"
#include "sculpt/rt/station_setup.hpp"
#include "sculpt/rt/transfer.hpp"
#include "session_log.hpp"
#include "view_state.hpp"

namespace sculpt::tools {
namespace {

using Clock = std::chrono::steady_clock;
// How long the model stays still before the view measures its splat sizes again.
constexpr double kSplatSettleS = 0.5;

// The station's fingertips start above the model: the camera frames this much more than the
// model's bounding sphere so that an approaching finger is in the picture.
constexpr double kFramingScale = 1.4;
constexpr int kViewerNice = 10;
constexpr render::Rgb kInk{0.12, 0.12, 0.15};
constexpr render::Rgb kAlarm{0.85, 0.05, 0.05};

void status_line(const std::string& text) {
  std::printf("view: %s\n", text.c_str());
  std::fflush(stdout);
}

class ViewCommand final : public Command {
 public:
  explicit ViewCommand(CLI::App& app) {
    sub_ = app.add_subcommand("view", "A window that follows the station over LCM, or plays a recorded session");
    sub_->add_option("scene", scene_path_, "Scene file (.toml): its base model is what the edits apply to")->required();
    auto* lcm = sub_->add_option("--lcm", url_, "Follow the station on this LCM URL (default: the scene's lcm.url)")
                    ->check(lcm_url_check());
    auto* log = sub_->add_option("--log", log_path_, "Play this recorded session (sculpt run's output.log)");
    lcm->excludes(log);
    sub_->add_option("--catch-up", catch_up_path_,
                     "The station's durable log: frames lost on the live channel are read from it")
        ->excludes(log);
    sub_->add_flag("--paused", paused_, "With --log: start paused")->needs(log);
    sub_->add_option("--fps", fps_, "Render at most this many pictures a second")
        ->check(finite_in(0.0, true, 30.0, false))
        ->default_val(30.0);
    sub_->add_option("--size", width_, "Window width in pixels (height is 3/4 of it)")
        ->check(CLI::Range(160, 2048))
        ->default_val(640);
    sub_->add_option("--up", up_, "The model's up axis: x | y | z")
        ->check(CLI::IsMember({"x", "y", "z"}))
        ->default_val("y");
    sub_->add_option("--azimuth", azimuth_, "Degrees about the up axis, 0 = front")
        ->check(finite_in(-360.0, false, 360.0, false, "degrees"))
        ->default_val(30.0);
    sub_->add_option("--elevation", elevation_, "Degrees above the horizon")
        ->check(finite_in(-90.0, false, 90.0, false, "degrees"))
        ->default_val(20.0);
    sub_->add_option("--arrow-scale", arrow_scale_, "Draw each force arrow this many times its length")
        ->check(finite_in(0.0, true, 1e6, false))
        ->default_val(1.0);
    sub_->add_option("--exit-after-idle", idle_s_,
                     "Quit when nothing arrived for this many seconds after the first message (with --log: after "
                     "the last frame played)")
        ->check(finite_in(0.0, true, 3600.0, false));
    sub_->add_option("--screenshot", screenshot_path_, "On exit, write what the window shows (.png)");
    sub_->add_option("--dump-model", dump_path_, "On exit, write the viewer's copy of the model");
  }

  bool chosen() const override { return sub_->parsed(); }

  int run() override {
    // llvmpipe starts one rasteriser thread per core unless told otherwise, before its first
    // context; the station needs those cores more than the viewer does.
    setenv("LP_NUM_THREADS", "1", 1);
    errno = 0;
    if (nice(kViewerNice) == -1 && errno != 0) std::perror("view: nice");
    // A recording that cannot be read should cost nothing: said before any window opens. (The
    // catch-up log may not exist yet: the station creates it when it starts.)
    if (!log_path_.empty()) {
      const std::string kind = base::non_regular_kind(log_path_);
      if (!kind.empty() || access(log_path_.c_str(), R_OK) != 0) {
        std::cerr << "sculpt view: error: " << log_path_
                  << ": cannot read: " << (kind.empty() ? std::strerror(errno) : kind + ", not a regular file") << "\n";
        return kExitFailure;
      }
    }
    // The catch-up log may not exist yet, but a folder or a device never becomes one: said now,
    // not as a failed catch-up when the first frame is missed.
    if (const std::string kind = catch_up_path_.empty() ? std::string() : base::non_regular_kind(catch_up_path_);
        !kind.empty()) {
      std::cerr << "sculpt view: error: --catch-up " << catch_up_path_ << ": " << kind
                << ", not the station's durable log (its output.log)\n";
      return kExitUsage;
    }
    try {
      const rt::Scene scene = rt::load_scene(scene_path_);
      try {
        check_outputs_before_the_window(scene);
      } catch (const std::invalid_argument& e) {
        std::cerr << "sculpt view: error: " << e.what() << "\n";
        return kExitUsage;
      }
      if (url_.empty()) url_ = scene.lcm.url;
      setup_.emplace(rt::prepare_station(scene));
      model_ = setup_->model;
      rt::TransferOptions options;
      options.field = setup_->settings.deform.field;  // as the station's deformer: the copy is bit for bit
      transfer_.emplace(model_, options);
      std::printf("model    %s: %zu points\n", scene.model.path.c_str(), model_.size());
    } catch (const rt::SceneError& e) {
      std::cerr << "sculpt view: error: " << e.what() << "\n";
      return kExitUsage;
    } catch (const std::exception& e) {
      std::cerr << "sculpt view: error: " << e.what() << "\n";
      return kExitFailure;
    }
    try {
      open_window();
      const int code = log_path_.empty() ? follow() : play();
      finish();
      return code;
    } catch (const std::exception& e) {
      std::cerr << "sculpt view: error: " << e.what() << "\n";
      return kExitFailure;
    }
  }

 private:
  // The picture and the model are written when the window closes, maybe after an hour's
  // session: a wrong extension or folder is refused before it opens, and neither may replace an
  // input (the base model is half of the edit history, the log the other).
  // @throw std::invalid_argument naming the option and what is wrong.
  void check_outputs_before_the_window(const rt::Scene& scene) const {
    if (!screenshot_path_.empty()) refuse_non_png_picture("--screenshot", screenshot_path_);
    if (!dump_path_.empty()) refuse_unwritable_model_format("--dump-model", dump_path_);
    const std::vector<NamedPath> outputs = {{"--screenshot", screenshot_path_}, {"--dump-model", dump_path_}};
    const std::vector<NamedPath> inputs = {{"the scene", scene_path_},
                                           {"the scene's model", scene.model.path},
                                           {"--log", log_path_},
                                           {"--catch-up", catch_up_path_}};
    check_outputs(outputs, inputs);
  }

  void open_window() {
    height_ = width_ * 3 / 4;
    window_ = std::make_unique<view::ImageWindow>(width_, height_, "sculpt view " + scene_path_);
    renderer_ = std::make_unique<render::ViewRenderer>(width_, height_, 1);
    up_axis_ = up_ == "x" ? render::UpAxis::kX : up_ == "z" ? render::UpAxis::kZ : render::UpAxis::kY;
    const render::Bounds box = render::bounds_of(model_);
    centre_ = box.centre();
    radius_ = kFramingScale * render::farthest_distance(model_, centre_);
    orbit_.emplace(view::ViewAngles{azimuth_, elevation_, 1.0});
    place_camera();
  }

  // The camera moves by the keys (OrbitView::key) and by the mouse: a left-button drag turns
  // the model, the wheel moves in and out. Each move places the camera and prints it.
  bool camera_key(view::Key key) { return moved(orbit_->key(key)); }

  void camera_pointer() {
    const view::PointerMotion m = window_->take_pointer();
    const bool dragged = (m.drag_x != 0.0 || m.drag_y != 0.0) && orbit_->drag(m.drag_x, m.drag_y, width_, height_);
    const bool scrolled = m.scroll != 0.0 && orbit_->scroll(m.scroll);
    moved(dragged || scrolled);
  }

  bool moved(bool changed) {
    if (!changed) return false;
    place_camera();
    dirty_ = true;
    return true;
  }

  void place_camera() {
    const view::ViewAngles& v = orbit_->angles();
    camera_ =
        render::fit_camera(centre_, v.zoom * radius_, render::look_direction(up_axis_, v.azimuth_deg, v.elevation_deg),
                           up_axis_, width_, height_);
    // Closer in, the model still reaches radius_ around its centre: the depth range keeps it all.
    const double distance = deform::norm(camera_.eye - camera_.target);
    camera_.near_distance = std::max(distance - 1.5 * radius_, 1e-3 * distance);
    camera_.far_distance = distance + 1.5 * radius_;
    const render::Camera& c = camera_;
    std::printf("view: camera eye %.9g %.9g %.9g target %.9g %.9g %.9g up %.9g %.9g %.9g fov %.9g size %dx%d\n",
                c.eye.x, c.eye.y, c.eye.z, c.target.x, c.target.y, c.target.z, c.up.x, c.up.y, c.up.z,
                c.vertical_fov_deg, c.width, c.height);
    std::fflush(stdout);
  }

  void apply_frame(std::span<const logging::CollisionRecord> frame) {
    try {
      transfer_->apply(frame);
    } catch (const std::invalid_argument& e) {
      // A frame the station applied and the copy cannot: the copy is no longer the station's.
      ++rejected_;
      status_line(std::string("frame rejected: ") + e.what());
    }
    state_.frame({frame.begin(), frame.end()});
    model_changed_ = true;
    dirty_ = true;
  }

  // Follows the live channels until a quit key, the window closing, or --exit-after-idle.
  int follow() {
    view::LcmReceiver receiver(url_);
    view::FrameFollower::CatchUpSource catch_up;
    if (!catch_up_path_.empty()) {
      catch_up = [log = std::make_shared<view::CatchUpLog>(catch_up_path_)](std::int64_t first, std::int64_t last) {
        return log->events(first, last);
      };
    }
    view::FrameFollower follower([this](std::span<const logging::CollisionRecord> f) { apply_frame(f); },
                                 std::move(catch_up));
    follower_ = &follower;
    status_line("following " + url_ + (catch_up_path_.empty() ? "" : ", catching up from " + catch_up_path_));
    std::optional<Clock::time_point> last_message;
    std::int64_t reported_diverged = 0;
    std::size_t reported_caught_up = 0;
    for (;;) {
      const std::vector<view::LiveMessage> messages = receiver.take();
      for (const view::LiveMessage& m : messages) {
        if (const auto* c = std::get_if<logging::CollisionRecord>(&m)) {
          follower.collision(*c, base::monotonic_now_ns());
        } else if (const auto* tip = std::get_if<view::FingertipSeen>(&m)) {
          state_.fingertip(*tip);
          dirty_ = true;
        } else if (const auto* tick = std::get_if<view::TickSeen>(&m)) {
          follower.tick(tick->tick, tick->collisions, base::monotonic_now_ns());
          state_.tick(*tick);
          dirty_ = true;
        }
      }
      follower.settle(base::monotonic_now_ns());
      if (!messages.empty()) last_message = Clock::now();
      const bool idle = idle_s_ > 0.0 && last_message &&
                        std::chrono::duration<double>(Clock::now() - *last_message).count() > idle_s_;
      if (idle) follower.finish();
      if (follower.diverged_frames() != reported_diverged || follower.frames_caught_up() != reported_caught_up) {
        reported_diverged = follower.diverged_frames();
        reported_caught_up = follower.frames_caught_up();
        status_line(follower_text());
        dirty_ = true;
      }
      if (quit_requested() || idle) break;
      draw_if_due(follower_text());
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    status_line("exit " + follower_text());
    last_text_ = follower_text();
    follower_ = nullptr;
    return kExitOk;
  }

  // Plays --log with the keys until a quit key, the window closing, or --exit-after-idle after
  // the last frame.
  int play() {
    const view::SessionLog log = view::read_session_log(log_path_);
    // Damage is skipped and said, and a frame it left short of its events is not played (its
    // forces were solved together; some of them alone would move the copy where the station
    // never went): what replay --skip-damage applies, so the copy stays the session's but for
    // the frames named here.
    if (log.damaged > 0) {
      status_line(log_path_ + ": " + std::to_string(log.damaged) +
                  " damaged or cut places skipped (sculpt replay names each by its byte offset)");
    }
    const std::span<const logging::CollisionRecord> events(log.collisions);
    std::vector<std::pair<std::size_t, std::size_t>> frames;  // [begin, end) of each whole frame's events
    for (std::size_t begin = 0; begin < events.size();) {
      const std::size_t end = logging::frame_run_end(events, begin);
      if (logging::whole_frame(events.subspan(begin, end - begin))) {
        frames.emplace_back(begin, end);
      } else {
        status_line("incomplete frame " + std::to_string(events[begin].frame_id) + " (" + std::to_string(end - begin) +
                    " of " + std::to_string(events[begin].frame_size) + " events): not played");
      }
      begin = end;
    }
    std::vector<double> times;
    for (const auto& f : frames) times.push_back(log.collisions[f.first].time_s);
    view::Playback playback(std::move(times), paused_);
    std::size_t applied = 0, tips = 0, ticks = 0;
    // The first status line says the window is up: whoever reads it may send keys at once.
    draw(playback.status());
    window_->poll();
    status_line(playback.status());
    auto last = Clock::now();
    std::optional<Clock::time_point> ended_at;
    for (;;) {
      for (const view::Key key : window_->poll()) {
        if (key == view::Key::kQuit) quit_ = true;
        if (camera_key(key)) continue;
        // Said before the clock moves on, so the line shows what the key did and nothing else.
        if (playback.key(key)) {
          status_line(playback.status());
          dirty_ = true;
        }
      }
      camera_pointer();
      bool changed = false;
      const auto now = Clock::now();
      playback.advance(std::chrono::duration<double>(now - last).count());
      last = now;
      while (applied < playback.due()) {
        const auto [begin, end] = frames[applied++];
        apply_frame(std::span(log.collisions).subspan(begin, end - begin));
      }
      // Fingertips and ticks up to the tick of the last frame applied (all of them at the end).
      const std::int64_t tick = playback.ended() ? INT64_MAX
                                : applied == 0   ? -1
                                                 : log.collisions[frames[applied - 1].first].tick;
      for (; tips < log.fingertips.size() && log.fingertips[tips].tick <= tick; ++tips)
        state_.fingertip(log.fingertips[tips]);
      for (; ticks < log.ticks.size() && log.ticks[ticks].tick <= tick; ++ticks) state_.tick(log.ticks[ticks]);
      if (playback.ended() && !ended_at) {
        ended_at = now;
        changed = true;
      }
      if (changed) {
        status_line(playback.status());
        dirty_ = true;
      }
      if (quit_ || window_->closed()) break;
      if (idle_s_ > 0.0 && ended_at && std::chrono::duration<double>(now - *ended_at).count() > idle_s_) break;
      draw_if_due(playback.status());
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    last_text_ = playback.status();
    return kExitOk;
  }

  std::string follower_text() const {
    const view::FrameFollower& f = *follower_;
    std::string text = "frame " + std::to_string(f.frame_id()) + " applied " + std::to_string(f.frames_applied()) +
                       " caught up " + std::to_string(f.frames_caught_up()) + " gaps " + std::to_string(f.gaps());
    if (f.diverged() || rejected_ > 0) {
      text += " DIVERGED by " + std::to_string(f.diverged_frames() + static_cast<std::int64_t>(rejected_)) + " frames";
    }
    return text;
  }

  bool quit_requested() {
    for (const view::Key key : window_->poll()) {
      if (key == view::Key::kQuit) quit_ = true;
      camera_key(key);
    }
    camera_pointer();
    return quit_ || window_->closed();
  }

  void draw_if_due(const std::string& text) {
    const auto now = Clock::now();
    if (splats_stale_ && std::chrono::duration<double>(now - last_change_).count() >= kSplatSettleS) {
      rebuild_render_model();
      dirty_ = true;
    }
    if (!dirty_ || (last_draw_ && std::chrono::duration<double>(now - *last_draw_).count() < 1.0 / fps_)) return;
    draw(text);
    last_draw_ = now;
  }

  // The drawn copy follows each changed frame (positions and normals); its splat sizes, which
  // follow each point's spacing and cost two hundred times the copy to measure (0.4 s on a
  // 437,645-point scan), are measured again once the model has been still for kSplatSettleS.
  void rebuild_render_model() {
    render_model_ = std::make_unique<render::RenderModel>(model_);
    model_changed_ = splats_stale_ = false;
  }

  void draw(const std::string& text) {
    if (!render_model_) {
      rebuild_render_model();
    } else if (model_changed_) {
      render_model_->follow(model_);
      model_changed_ = false;
      splats_stale_ = !render_model_->splat_classes().empty();
      last_change_ = Clock::now();
    }
    render::Image image = renderer_->render(*render_model_, camera_, {}, state_.overlay(arrow_scale_));
    const bool alarm = text.find("DIVERGED") != std::string::npos;
    render::draw_text(image, 8, 8, text, alarm ? kAlarm : kInk, 2);
    render::draw_text(image, 8, 8 + render::text_height(text, 2) + 6, state_.tick_text(), kInk, 1);
    window_->show(image);
    dirty_ = false;
  }

  void finish() {
    if (splats_stale_ || model_changed_) rebuild_render_model();  // the last picture with its splats measured
    draw(last_text_);
    // The X server draws asynchronously: let it take the last picture before it is read back.
    window_->poll();
    if (!screenshot_path_.empty()) {
      write_picture_output(screenshot_path_, window_->capture());
    }
    if (!dump_path_.empty()) {
      write_model_output(dump_path_, model_);
    }
  }

  CLI::App* sub_ = nullptr;
  std::string scene_path_, url_, log_path_, catch_up_path_, up_, screenshot_path_, dump_path_;
  bool paused_ = false;
  double fps_ = 30.0, azimuth_ = 30.0, elevation_ = 20.0, arrow_scale_ = 1.0, idle_s_ = 0.0;
  int width_ = 640, height_ = 480;

  std::optional<rt::StationSetup> setup_;
  deform::PointModel model_;
  std::optional<rt::FrameTransfer> transfer_;
  view::ViewState state_;
  view::FrameFollower* follower_ = nullptr;
  std::size_t rejected_ = 0;
  std::unique_ptr<view::ImageWindow> window_;
  std::unique_ptr<render::ViewRenderer> renderer_;
  std::unique_ptr<render::RenderModel> render_model_;
  render::Camera camera_;
  render::UpAxis up_axis_ = render::UpAxis::kY;
  render::Vec3 centre_;
  double radius_ = 1.0;
  std::optional<view::OrbitView> orbit_;  // from the window's opening
  bool model_changed_ = true, dirty_ = true, quit_ = false;
  std::optional<Clock::time_point> last_draw_;
  bool splats_stale_ = false;      // the drawn copy moved since its splat sizes were measured
  Clock::time_point last_change_;  // when it last moved
  std::string last_text_;
};

}  // namespace

std::unique_ptr<Command> add_view_command(CLI::App& app) { return std::make_unique<ViewCommand>(app); }

}  // namespace sculpt::tools
