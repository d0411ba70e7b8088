#pragma once
// Shot keys as options of `pathfarm local` and `pathfarm submit` (docs/shot-format.md),
// set over the shot file's or the scene file's: --frames, --res, --spp, --max-depth,
// --pipeline, --name, --output, --reference-spp, and --set KEY=VALUE for any other key.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace pathfarm {

struct ShotKeyArguments {
  std::string frames;
  std::string resolution;
  int spp = 0;
  int maxDepth = -1;
  std::string pipeline;
  std::string name;
  std::string output;
  std::string referenceSpp;
  std::vector<std::string> set;
};

void addShotKeyOptions(CLI::App* command, ShotKeyArguments& arguments);

// The keys as a JSON object; throws UsageError (cli/usage_parsing.h) naming a malformed option.
nlohmann::json shotKeysOf(const ShotKeyArguments& arguments);

}  // namespace pathfarm
