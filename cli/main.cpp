// pathfarm: one executable, one subcommand per job (docs in README.md).
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>

#include "cli/render_command.h"

int main(int argc, char** argv) {
  CLI::App app{"pathfarm: renders animations with Monte Carlo light transport"};
  app.require_subcommand(1);
  bool verbose = false;
  app.add_flag("-v,--verbose", verbose, "log debugging detail");
  const auto runRender = pathfarm::addRenderCommand(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return 2;  // usage errors share the exit status of bad input files
  }
  spdlog::set_level(verbose ? spdlog::level::debug : spdlog::level::info);
  spdlog::set_pattern("[%H:%M:%S] %^%l%$ %v");
  if (app.got_subcommand("render")) return runRender();
  return 2;
}
