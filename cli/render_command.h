#pragma once
// `pathfarm render SCENE --frames A:B --spp N --res WxH --out DIR [--threads N] ...`
#include <CLI/CLI.hpp>

namespace pathfarm {

// Registers the subcommand; the returned function runs it and gives the exit status.
std::function<int()> addRenderCommand(CLI::App& app);

}  // namespace pathfarm
