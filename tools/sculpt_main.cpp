// sculpt: glovesculpt's command line.
#include <CLI/CLI.hpp>

#include <iostream>
#include <memory>
#include <vector>

#include "commands.hpp"

int main(int argc, char** argv) {
  using namespace sculpt::tools;
  CLI::App app{"sculpt: physically based sculpting of point clouds with an electronic glove"};
  app.require_subcommand(1);
  std::vector<std::unique_ptr<Command>> commands;
  commands.push_back(add_deform_command(app));
  commands.push_back(add_generate_command(app));
  commands.push_back(add_run_command(app));
  commands.push_back(add_glove_sim_command(app));
  commands.push_back(add_replay_command(app));
  commands.push_back(add_check_command(app));
  commands.push_back(add_render_command(app));
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help
    std::cerr << "sculpt: error: " << e.what() << " (see sculpt --help)\n";
    return kExitUsage;
  }
  for (const auto& command : commands) {
    if (command->chosen()) return command->run();
  }
  return kExitUsage;
}
