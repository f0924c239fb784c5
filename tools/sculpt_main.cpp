// sculpt: glovesculpt's command line.
#include <CLI/CLI.hpp>

#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "commands.hpp"
#include "did_you_mean.hpp"
#include "sculpt/base/version.hpp"

int main(int argc, char** argv) {
  using namespace sculpt::tools;
  CLI::App app{"sculpt: physically based sculpting of point clouds with an electronic glove"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("sculpt ") + sculpt::base::project_version());
  std::vector<std::unique_ptr<Command>> commands;
  commands.push_back(add_deform_command(app));
  commands.push_back(add_generate_command(app));
  commands.push_back(add_order_command(app));
  commands.push_back(add_run_command(app));
  commands.push_back(add_glove_sim_command(app));
  commands.push_back(add_replay_command(app));
  commands.push_back(add_check_command(app));
  commands.push_back(add_render_command(app));
  commands.push_back(add_report_command(app));
#if SCULPT_HAS_VIEW
  commands.push_back(add_view_command(app));
#endif
  // A first word that is no subcommand is a typo far more often than anything else; CLI11
  // would only say that a subcommand is required.
  if (argc > 1 && argv[1][0] != '-') {
    std::vector<std::string> names;
    for (const CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) names.push_back(sub->get_name());
    const std::string word = argv[1];
    if (std::find(names.begin(), names.end(), word) == names.end()) {
      const std::string near = did_you_mean(word, names);
      std::cerr << "sculpt: error: '" << word << "' is not a subcommand"
                << (near.empty() ? std::string() : " (did you mean '" + near + "'?)") << " (see sculpt --help)\n";
      return kExitUsage;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    std::cerr << "sculpt: error: " << e.what() << " (see sculpt --help)\n";
    return kExitUsage;
  }
  for (const auto& command : commands) {
    if (command->chosen()) return command->run();
  }
  return kExitUsage;
}
