#pragma once
// The sculpt subcommands. Each registers its options on the CLI11 app and runs after parsing;
// CLI11 stays out of this header because it is slow to compile.

#include <memory>

namespace CLI {  // NOLINT(readability-identifier-naming): CLI11's own
class App;
}

namespace sculpt::tools {

/// Exit codes of every subcommand.
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;  ///< the input could not be processed (unreadable model, ...)
inline constexpr int kExitUsage = 2;    ///< bad arguments
/// The edit history is damaged or incomplete, and the model was still written: `replay
/// --strict` read damage in the log; `run` could not write every event to its log.
inline constexpr int kExitDamage = 3;

/// A registered subcommand: run() is called when the user chose it.
class Command {
 public:
  virtual ~Command() = default;
  virtual bool chosen() const = 0;
  virtual int run() = 0;
};

std::unique_ptr<Command> add_deform_command(CLI::App& app);
std::unique_ptr<Command> add_generate_command(CLI::App& app);
std::unique_ptr<Command> add_order_command(CLI::App& app);
std::unique_ptr<Command> add_run_command(CLI::App& app);
std::unique_ptr<Command> add_glove_sim_command(CLI::App& app);
std::unique_ptr<Command> add_replay_command(CLI::App& app);
std::unique_ptr<Command> add_check_command(CLI::App& app);
std::unique_ptr<Command> add_render_command(CLI::App& app);
std::unique_ptr<Command> add_report_command(CLI::App& app);
/// Only in builds with LCM (SCULPT_HAS_VIEW): the viewer follows the station's live channels.
std::unique_ptr<Command> add_view_command(CLI::App& app);

}  // namespace sculpt::tools
