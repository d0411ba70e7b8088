// `pathfarm compare A.exr REF.exr` and `pathfarm compare-seq DIR_A DIR_REF`: error
// metrics for people (a table) and machines (--json).
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <optional>
#include <utility>
#include <nlohmann/json.hpp>

#include "cli/command.h"
#include "image/exr_io.h"
#include "postproc/metrics/image_metrics.h"

namespace pathfarm {
namespace {

struct CompareArguments {
  std::string image, reference;
  std::string layer;
  std::string crop;
  std::string mask;  // compare: EXR[:CHANNEL[&BITS|=VALUE]]
  bool outsideMask = false;
  bool json = false;
};

std::optional<Crop> parseCrop(const std::string& text) {
  if (text.empty()) return std::nullopt;
  Crop c;
  char tail = 0;
  if (std::sscanf(text.c_str(), "%d,%d,%d,%d%c", &c.x0, &c.y0, &c.x1, &c.y1, &tail) != 4)
    throw std::invalid_argument("--crop \"" + text + "\": expected X0,Y0,X1,Y1");
  return c;
}

// `--mask EXR[:CHANNEL[&BITS|=VALUE]]`: the pixels where the channel (rerender.Y by
// default) is above 0.5, or, read as a whole number, has any of BITS set or equals VALUE
// (the interpolate task's `rerender_causes.Y`: `&16` every pixel the feature mismatch
// flagged, `=16` those it flagged alone); with `outside` the others.
std::optional<std::vector<uint8_t>> parseMask(const std::string& text, bool outside) {
  if (text.empty()) {
    if (outside) throw std::invalid_argument("--outside-mask needs --mask");
    return std::nullopt;
  }
  const size_t colon = text.rfind(':');
  const bool named = colon != std::string::npos && text.find('/', colon) == std::string::npos;
  const std::string file = named ? text.substr(0, colon) : text;
  std::string channel = named ? text.substr(colon + 1) : "rerender.Y";
  const size_t test = channel.find_first_of("&=");
  std::optional<std::pair<char, long>> number;
  if (test != std::string::npos) {
    const std::string operand = channel.substr(test + 1);
    char* end = nullptr;
    const long value = std::strtol(operand.c_str(), &end, 10);
    if (operand.empty() || *end != '\0' || value < 0)
      throw std::invalid_argument("--mask " + text + ": expected CHANNEL&BITS or CHANNEL=VALUE with a whole number");
    number = std::make_pair(channel[test], value);
    channel.resize(test);
  }
  const FrameImage frame = readExr(file);
  if (!frame.hasChannel(channel)) throw std::invalid_argument("--mask " + file + ": no channel " + channel);
  const std::vector<float>& values = frame.channel(channel);
  std::vector<uint8_t> mask(values.size());
  for (size_t p = 0; p < values.size(); ++p) {
    bool inside = values[p] > 0.5f;
    if (number) {
      const long whole = std::isfinite(values[p]) ? std::lround(values[p]) : -1;
      inside = number->first == '&' ? whole >= 0 && (whole & number->second) != 0 : whole == number->second;
    }
    mask[p] = inside != outside;
  }
  return mask;
}

nlohmann::json toJson(const ImageMetrics& m) {
  return {{"relmse", m.relMse}, {"mse", m.mse},         {"psnr", m.psnr},
          {"smape", m.smape},   {"brightness", m.brightness}, {"compared", m.compared},
          {"skipped_reference", m.skippedReference},
          {"nonfinite", m.nonFinite}, {"worst_tile_relmse", m.worstTileRelMse},
          {"worst_percent_share", m.worstPercentShare}};
}

void printTable(const std::string& label, const ImageMetrics& m) {
  std::printf("%-24s relMSE %.6g  MSE %.6g  PSNR %.2f dB  SMAPE %.6g  brightness %.4f  worst tile %.6g  "
              "worst 1%% %.1f%%\n",
              label.c_str(), m.relMse, m.mse, m.psnr, m.smape, m.brightness, m.worstTileRelMse, 100 * m.worstPercentShare);
  if (m.skippedReference > 0) std::printf("  skipped %zu non-finite reference values\n", m.skippedReference);
  if (m.nonFinite > 0) std::printf("  %zu non-finite values in the image were left out\n", m.nonFinite);
}

// The frame_*.exr files of a folder, by name.
std::vector<std::filesystem::path> frameFilesIn(const std::filesystem::path& folder) {
  if (!std::filesystem::is_directory(folder)) throw std::invalid_argument(folder.string() + ": not a folder");
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("frame_", 0) == 0 && entry.path().extension() == ".exr") files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}


int runCompare(const CompareArguments& a) {
  return runReportingBadInput([&] {
    const FrameImage image = readExr(a.image), reference = readExr(a.reference);
    const std::optional<std::vector<uint8_t>> mask = parseMask(a.mask, a.outsideMask);
    if (mask && mask->size() != image.pixelCount()) throw std::invalid_argument("--mask: the mask's frame has another size");
    const ImageMetrics m = compareImages(image, reference, layerChannels(reference, a.layer), parseCrop(a.crop),
                                         mask ? &*mask : nullptr);
    if (a.json) {
      std::printf("%s\n", toJson(m).dump(2).c_str());
    } else {
      printTable(a.layer.empty() ? "beauty" : a.layer, m);
    }
    return kExitOk;
  });
}

int runCompareSequence(const CompareArguments& a) {
  return runReportingBadInput([&] {
    const auto files = frameFilesIn(a.image);
    std::vector<FrameImage> images, references;
    for (const auto& file : files) {
      const auto reference = std::filesystem::path(a.reference) / file.filename();
      if (!std::filesystem::exists(reference)) continue;
      images.push_back(readExr(file));
      references.push_back(readExr(reference));
    }
    if (images.empty()) throw std::invalid_argument("no frame_*.exr appears in both folders");
    const SequenceMetrics s =
        compareSequences(images, references, layerChannels(references[0], a.layer), parseCrop(a.crop));
    if (a.json) {
      nlohmann::json frames = nlohmann::json::array();
      for (const ImageMetrics& m : s.frames) frames.push_back(toJson(m));
      std::printf("%s\n", nlohmann::json{{"frames", frames}, {"mean_relmse", s.meanRelMse},
                                         {"temporal_relmse", s.temporalRelMse}}
                               .dump(2)
                               .c_str());
    } else {
      size_t i = 0;
      for (const auto& file : files) {
        if (i < s.frames.size() && std::filesystem::exists(std::filesystem::path(a.reference) / file.filename()))
          printTable(file.filename().string(), s.frames[i++]);
      }
      std::printf("mean relMSE %.6g, temporal relMSE (flicker) %.6g over %zu frames\n", s.meanRelMse,
                  s.temporalRelMse, s.frames.size());
    }
    return kExitOk;
  });
}

void addCommonOptions(CLI::App* command, CompareArguments& a) {
  command->add_option("--layer", a.layer, "layer to compare, e.g. diffuse_direct.color (default: beauty R,G,B)");
  command->add_option("--crop", a.crop, "X0,Y0,X1,Y1: compare only this window");
  command->add_flag("--json", a.json, "print JSON");
}

}  // namespace

std::vector<Command> addMetricsCommands(CLI::App& app) {
  auto single = std::make_shared<CompareArguments>();
  CLI::App* compare = app.add_subcommand("compare", "error of an EXR frame against a reference (relMSE, MSE, PSNR, SMAPE)");
  compare->add_option("image", single->image, "EXR to judge")->required();
  compare->add_option("reference", single->reference, "reference EXR")->required();
  addCommonOptions(compare, *single);
  compare->add_option("--mask", single->mask,
                      "EXR[:CHANNEL[&BITS|=VALUE]]: compare only the pixels where CHANNEL (default rerender.Y, a "
                      "frame's re-rendered pixels) is above 0.5, or as a whole number has any of BITS set or equals "
                      "VALUE (an interpolate task's rerender_causes.Y)");
  compare->add_flag("--outside-mask", single->outsideMask, "compare the other pixels instead");

  auto sequence = std::make_shared<CompareArguments>();
  CLI::App* seq = app.add_subcommand("compare-seq", "per-frame and temporal error of frame_*.exr sequences");
  seq->add_option("images", sequence->image, "folder of frames to judge")->required();
  seq->add_option("references", sequence->reference, "folder of reference frames")->required();
  addCommonOptions(seq, *sequence);
  return {{compare, [single] { return runCompare(*single); }}, {seq, [sequence] { return runCompareSequence(*sequence); }}};
}

}  // namespace pathfarm
