// pathfarm: one executable, one subcommand per job (see README.md).
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>

#include "cli/command.h"
#include "image/plane_memory.h"

int main(int argc, char** argv) {
  pathfarm::keepFreedPlanesForReuse();
  CLI::App app{"pathfarm: renders animations with Monte Carlo light transport on a farm"};
  app.require_subcommand(1);
  bool verbose = false;
  app.add_flag("-v,--verbose", verbose, "log debugging detail");
  std::vector<pathfarm::Command> commands;
  for (auto add : {pathfarm::addRenderCommand, pathfarm::addFarmProcessCommands, pathfarm::addClientCommands,
                   pathfarm::addLocalCommand, pathfarm::addPreviewCommand, pathfarm::addMetricsCommands,
                   pathfarm::addFilterCommands, pathfarm::addFlowCommand,
                   pathfarm::addInterpolationCommands, pathfarm::addPoissonCommand}) {
    for (pathfarm::Command& command : add(app)) commands.push_back(std::move(command));
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return pathfarm::kExitBadInput;
  }
  // Logs on standard error: standard output carries what scripts read (`id=$(pathfarm
  // submit ...)`, listings, reports).
  spdlog::set_default_logger(spdlog::stderr_color_mt("pathfarm"));
  spdlog::set_level(verbose ? spdlog::level::debug : spdlog::level::info);
  spdlog::set_pattern("[%H:%M:%S] %^%l%$ %v");
  for (const pathfarm::Command& command : commands) {
    if (command.app->parsed()) return command.run();
  }
  return pathfarm::kExitBadInput;
}
