#include "client/frame_names.h"

#include <cstdio>
#include <regex>
#include <stdexcept>

namespace pathfarm::farm {
namespace {

struct Fields {
  int64_t frame;
  const std::string& shot;
  int64_t id;
};

// The pattern with every field replaced; throws std::invalid_argument for a bad field.
std::string expand(const std::string& pattern, const Fields& fields) {
  static const std::regex padded("frame:0([1-9])d");
  std::string out;
  for (size_t i = 0; i < pattern.size(); ++i) {
    if (pattern[i] != '{') {
      out += pattern[i];
      continue;
    }
    const size_t close = pattern.find('}', i);
    if (close == std::string::npos) throw std::invalid_argument("--frame-names: a '{' without its '}'");
    const std::string field = pattern.substr(i + 1, close - i - 1);
    std::smatch match;
    if (field == "shot") {
      out += fields.shot;
    } else if (field == "id") {
      out += std::to_string(fields.id);
    } else if (field == "frame") {
      out += std::to_string(fields.frame);
    } else if (std::regex_match(field, match, padded)) {
      char text[32];
      std::snprintf(text, sizeof text, "%0*lld", std::stoi(match[1]), static_cast<long long>(fields.frame));
      out += text;
    } else {
      throw std::invalid_argument("--frame-names: unknown field {" + field +
                                  "} (fields: {shot}, {id}, {frame}, {frame:0Nd})");
    }
    i = close;
  }
  return out;
}

}  // namespace

FrameNames::FrameNames(std::string pattern) : pattern_(std::move(pattern)) {
  if (pattern_.find("{frame") == std::string::npos)
    throw std::invalid_argument("--frame-names: the name needs {frame} (or {frame:0Nd}), else every frame gets one name");
  const std::filesystem::path sample = nameOf(1, "shot", 1);  // checks the fields
  if (sample.is_absolute() || sample.empty())
    throw std::invalid_argument("--frame-names: a name relative to the output folder");
  for (const auto& part : sample)
    if (part == "..") throw std::invalid_argument("--frame-names: \"..\" would leave the output folder");
}

std::filesystem::path FrameNames::nameOf(int64_t frame, const std::string& shot, int64_t id) const {
  return expand(pattern_, {frame, shot, id});
}

std::vector<std::filesystem::path> renameFrames(const std::vector<std::filesystem::path>& frames,
                                                const std::filesystem::path& folder, const FrameNames& names,
                                                const std::string& shot, int64_t id) {
  static const std::regex fetched("frame_([0-9]+)\\.exr");
  std::vector<std::filesystem::path> renamed;
  for (const auto& frame : frames) {
    std::smatch match;
    const std::string file = frame.filename().string();
    if (!std::regex_match(file, match, fetched)) throw std::invalid_argument(frame.string() + ": not a fetched frame");
    const std::filesystem::path target = folder / names.nameOf(std::stoll(match[1]), shot, id);
    std::filesystem::create_directories(target.parent_path());
    std::filesystem::rename(frame, target);
    renamed.push_back(target);
  }
  return renamed;
}

}  // namespace pathfarm::farm
