#include "cli/shot_key_options.h"

#include "cli/usage_parsing.h"

namespace pathfarm {
namespace {

// As JSON where the text reads as JSON (numbers, arrays, objects, true), else as a string.
nlohmann::json jsonOrString(const std::string& text) {
  nlohmann::json parsed = nlohmann::json::parse(text, nullptr, false);
  return parsed.is_discarded() ? nlohmann::json(text) : parsed;
}

}  // namespace

void addShotKeyOptions(CLI::App* command, ShotKeyArguments& a) {
  command->add_option("--frames", a.frames, "frames A:B (inclusive), or one frame A (shot key \"frames\")");
  command->add_option("--res", a.resolution, "resolution WIDTHxHEIGHT (shot key \"resolution\")");
  command->add_option("--spp", a.spp, "samples per pixel (shot key \"spp\")")->check(CLI::PositiveNumber);
  command->add_option("--max-depth", a.maxDepth, "scattering events per path (shot key \"max_depth\")");
  command->add_option("--pipeline", a.pipeline, "auto, dui, di, du, d, tgpt, pssmlt, mlt, tmlt or pt (shot key \"pipeline\")");
  command->add_option("--name", a.name, "the shot's name (shot key \"name\")");
  command->add_option("--output", a.output, "the shot's output folder, relative to its file (shot key \"output\")");
  command->add_option("--reference-spp", a.referenceSpp, "render references at this spp, or \"auto\" (shot key \"reference_spp\")");
  command->add_option("--set", a.set, "KEY=VALUE: any other shot key, VALUE as JSON or else as a string (repeatable)");
}

nlohmann::json shotKeysOf(const ShotKeyArguments& a) {
  nlohmann::json keys = nlohmann::json::object();
  for (const std::string& assignment : a.set) {
    const size_t equals = assignment.find('=');
    if (equals == std::string::npos || equals == 0)
      throw UsageError("--set \"" + assignment + "\": expected KEY=VALUE");
    keys[assignment.substr(0, equals)] = jsonOrString(assignment.substr(equals + 1));
  }
  if (!a.frames.empty()) {
    const auto [start, end] = parseFrames(a.frames);
    keys["frames"] = {{"start", start}, {"end", end}};
  }
  if (!a.resolution.empty()) {
    const auto [width, height] = parseResolution(a.resolution);
    keys["resolution"] = {width, height};
  }
  if (a.spp > 0) keys["spp"] = a.spp;
  if (a.maxDepth >= 0) keys["max_depth"] = a.maxDepth;
  if (!a.pipeline.empty()) keys["pipeline"] = a.pipeline;
  if (!a.name.empty()) keys["name"] = a.name;
  if (!a.output.empty()) keys["output"] = a.output;
  if (!a.referenceSpp.empty()) keys["reference_spp"] = jsonOrString(a.referenceSpp);
  return keys;
}

}  // namespace pathfarm
