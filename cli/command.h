#pragma once
// A subcommand of `pathfarm`: where CLI11 parsed its arguments, and what runs it.
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>

#include <functional>
#include <vector>

namespace pathfarm {

struct Command {
  CLI::App* app;
  std::function<int()> run;  // returns the exit status
};

// Exit statuses shared by every command.
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;   // the work failed (rendering, the farm, a failed shot)
inline constexpr int kExitBadInput = 2;  // bad arguments, scene or shot file; nothing was done

// Runs a command whose every failure is bad input (a missing or damaged file, layer,
// size or option): the message is logged and the exit status is kExitBadInput.
template <class Body>
int runReportingBadInput(Body body) {
  try {
    return body();
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return kExitBadInput;
  }
}

std::vector<Command> addRenderCommand(CLI::App& app);
std::vector<Command> addFarmProcessCommands(CLI::App& app);  // scheduler, worker
std::vector<Command> addClientCommands(CLI::App& app);       // submit, status, watch, fetch, ...
std::vector<Command> addLocalCommand(CLI::App& app);
std::vector<Command> addPreviewCommand(CLI::App& app);
std::vector<Command> addMetricsCommands(CLI::App& app);  // compare, compare-seq
std::vector<Command> addFilterCommands(CLI::App& app);   // denoise, upsample
std::vector<Command> addFlowCommand(CLI::App& app);
std::vector<Command> addInterpolationCommands(CLI::App& app);  // interpolate, motionblur
std::vector<Command> addPoissonCommand(CLI::App& app);

}  // namespace pathfarm
