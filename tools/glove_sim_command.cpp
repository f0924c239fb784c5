// sculpt glove-sim: the simulated glove as a separate process, writing the wire protocol to a
// serial device or publishing over LCM: the glove of hardware-in-the-loop tests.
#include <CLI/CLI.hpp>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <memory>

#include "commands.hpp"
#include "lcm_url_option.hpp"
#include "number_check.hpp"
#include "sculpt/base/time_limits.hpp"
#include "sculpt/hal/serial_frame_writer.hpp"
#include "sculpt/hal/sim_script.hpp"
#include "sculpt/rt/fixed_rate_loop.hpp"
#include "sculpt/rt/scene.hpp"
#include "serial_device_check.hpp"
#if SCULPT_HAS_LCM
#include <lcm/lcm-cpp.hpp>

#include "sculpt/logging/channels.hpp"
#include "sculpt/hal/lcm_messages.hpp"
#endif

namespace sculpt::tools {
namespace {

std::atomic<bool> g_stop{false};
extern "C" void on_sim_signal(int) { g_stop.store(true); }

/// Where the samples go.
class SampleSink {
 public:
  virtual ~SampleSink() = default;
  virtual bool send(const hal::GloveSample& sample) = 0;
  /// Called after a failed send, at most every 200 ms: try to get the device back.
  virtual bool recover() = 0;
};

class SerialSink final : public SampleSink {
 public:
  explicit SerialSink(const std::string& device) : writer_(device) {}
  bool send(const hal::GloveSample& s) override { return writer_.write_sample(s); }
  bool recover() override { return writer_.reopen(); }

 private:
  hal::SerialFrameWriter writer_;
};

#if SCULPT_HAS_LCM
class LcmSink final : public SampleSink {
 public:
  LcmSink(const std::string& url, std::string channel) : lcm_(url), channel_(std::move(channel)) {
    if (!lcm_.good()) throw std::runtime_error("lcm: cannot open " + url);
  }
  bool send(const hal::GloveSample& s) override {
    sculpt_lcm::glove_sample_t message;
    hal::to_lcm(s, base::wall_time_us(), message);  // wall clock: monotonic times never go on the wire
    return lcm_.publish(channel_, &message) == 0;
  }
  bool recover() override { return lcm_.good(); }

 private:
  lcm::LCM lcm_;
  std::string channel_;
};
#endif

class GloveSimCommand final : public Command {
 public:
  explicit GloveSimCommand(CLI::App& app) {
    sub_ = app.add_subcommand("glove-sim", "Play a scene's simulated glove into a serial device or over LCM");
    sub_->add_option("scene", scene_path_, "Scene file with a glove.sim script")->required();
    auto* serial = sub_->add_option("--serial", serial_, "Serial device to write the wire protocol to");
    auto* lcm = sub_->add_option("--lcm", lcm_url_, "LCM URL to publish glove samples on")->check(lcm_url_check());
    // A channel given with --serial would be ignored: refused instead.
    sub_->add_option("--channel", channel_, "LCM channel (with --lcm)")
        ->default_val("SCULPT_GLOVE")
        ->check(lcm_channel_check())
        ->needs(lcm);
    serial->excludes(lcm);
    sub_->add_option("--duration", duration_s_, "Stop after this many seconds")
        ->check(positive_up_to(base::kMaxDurationS, "seconds: at most a year"));
  }
  bool chosen() const override { return sub_->parsed(); }

  int run() override {
    if (serial_.empty() == lcm_url_.empty()) {
      std::cerr << "sculpt glove-sim: error: give exactly one of --serial DEVICE or --lcm URL\n";
      return kExitUsage;
    }
    std::unique_ptr<hal::SimScript> script;
    try {
      const rt::Scene scene = rt::load_scene(scene_path_);
      if (scene.glove.config.backend != hal::Backend::kSim) {
        throw std::invalid_argument(scene_path_ + ": glove.backend is not \"sim\": it has no glove.sim script");
      }
      script = std::make_unique<hal::SimScript>(scene.glove.config.sim);
    } catch (const std::exception& e) {
      std::cerr << "sculpt glove-sim: error: " << e.what() << "\n";
      return kExitUsage;
    }
    // The writer retries a device that goes away; one that never was a serial line would only
    // count undelivered samples.
    if (!serial_.empty()) {
      if (const std::string why = serial_device_problem(serial_); !why.empty()) {
        std::cerr << "sculpt glove-sim: error: --serial " << serial_ << ": " << why << "\n";
        return kExitFailure;
      }
    }
    try {
      std::unique_ptr<SampleSink> sink;
      if (!serial_.empty()) sink = std::make_unique<SerialSink>(serial_);
#if SCULPT_HAS_LCM
      if (!lcm_url_.empty()) sink = std::make_unique<LcmSink>(lcm_url_, channel_);
#else
      if (!lcm_url_.empty()) throw std::runtime_error("LCM was left out of this build (SCULPT_WITH_LCM=OFF)");
#endif
      return play(*script, *sink);
    } catch (const std::exception& e) {
      std::cerr << "sculpt glove-sim: error: " << e.what() << "\n";
      return kExitFailure;
    }
  }

 private:
  int play(hal::SimScript& script, SampleSink& sink) {
    struct sigaction action {};
    action.sa_handler = on_sim_signal;
    sigaction(SIGINT, &action, nullptr);
    sigaction(SIGTERM, &action, nullptr);
    signal(SIGPIPE, SIG_IGN);
    const std::int64_t start = rt::monotonic_now_ns();
    const std::int64_t end = duration_s_ > 0.0 ? start + static_cast<std::int64_t>(duration_s_ * 1e9) : INT64_MAX;
    std::uint64_t sent = 0, failed = 0, recovered = 0;
    std::int64_t next_recovery = 0;
    bool broken = false;
    hal::GloveSample sample;
    while (!g_stop.load() && script.next(sample)) {
      // Each sample leaves at its own device time: the script's clock is the glove's clock.
      const std::int64_t due = start + static_cast<std::int64_t>(sample.device_time_us) * 1000;
      if (due > end) break;
      rt::sleep_until_ns(due);
      const std::int64_t now = rt::monotonic_now_ns();
      if (broken) {
        if (now < next_recovery) {
          ++failed;
          continue;
        }
        broken = !sink.recover();
        next_recovery = now + 200'000'000;
        if (broken) {
          ++failed;
          continue;
        }
        ++recovered;
      }
      if (sink.send(sample)) {
        ++sent;
      } else {
        ++failed;
        broken = true;
        next_recovery = now + 200'000'000;
      }
    }
    std::printf(
        "glove-sim: %llu samples sent, %llu not delivered (device gone), %llu recoveries, %llu dropped by the script\n",
        static_cast<unsigned long long>(sent), static_cast<unsigned long long>(failed),
        static_cast<unsigned long long>(recovered), static_cast<unsigned long long>(script.dropped()));
    return kExitOk;
  }

  CLI::App* sub_ = nullptr;
  std::string scene_path_, serial_, lcm_url_, channel_;
  double duration_s_ = 0.0;
};

}  // namespace

std::unique_ptr<Command> add_glove_sim_command(CLI::App& app) { return std::make_unique<GloveSimCommand>(app); }

}  // namespace sculpt::tools
