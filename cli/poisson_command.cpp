// `pathfarm poisson DIR --window 10 --overlap 5 --norm l1|l2 --out DIR`: screened Poisson
// reconstruction of a gradient-domain render's frames (docs/gradient-domain.md).
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <regex>

#include "cli/command.h"
#include "image/exr_io.h"
#include "postproc/poisson/window_blend.h"

namespace pathfarm {
namespace {

struct PoissonArguments {
  std::string in, out, norm = "l2";
  size_t window = 10, overlap = 5;
  PoissonSettings settings;
};

struct NumberedFrame {
  long long number;
  std::filesystem::path file;
};

// DIR's frame_NNNN.exr files in frame order; they must be consecutive, since a temporal
// difference always points at the next frame.
std::vector<NumberedFrame> consecutiveFramesIn(const std::filesystem::path& folder) {
  if (!std::filesystem::is_directory(folder)) throw std::invalid_argument(folder.string() + ": no such folder");
  const std::regex name("frame_([0-9]+)\\.exr");
  std::vector<NumberedFrame> frames;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    std::smatch match;
    const std::string file = entry.path().filename().string();
    if (std::regex_match(file, match, name)) frames.push_back({std::stoll(match[1]), entry.path()});
  }
  if (frames.empty()) throw std::invalid_argument(folder.string() + ": no frame_NNNN.exr files");
  std::sort(frames.begin(), frames.end(), [](const auto& a, const auto& b) { return a.number < b.number; });
  for (size_t i = 1; i < frames.size(); ++i)
    if (frames[i].number != frames[i - 1].number + 1)
      throw std::invalid_argument(folder.string() + ": frames " + std::to_string(frames[i - 1].number) + " and " +
                                  std::to_string(frames[i].number) + " are not consecutive");
  return frames;
}

int runPoisson(PoissonArguments& a) {
  return runReportingBadInput([&] {
    a.settings.norm = parsePoissonNorm(a.norm);
    if (a.overlap >= a.window) throw std::invalid_argument("--overlap must be smaller than --window");
    const std::vector<NumberedFrame> frames = consecutiveFramesIn(a.in);
    // Check the first frame before any work, so a wrong folder fails at once.
    const FrameImage first = readExr(frames[0].file);
    GradientFrame::fromImage(first, frames[0].file.string());
    const std::filesystem::path out(a.out);
    std::filesystem::create_directories(out);
    const std::string description = a.norm + ", alpha " + std::to_string(a.settings.alpha) + ", window " +
                                    std::to_string(a.window) + ", overlap " + std::to_string(a.overlap);
    spdlog::info("reconstructing {} frames of {} ({})", frames.size(), a.in, description);
    std::map<std::string, std::string> attributes;
    const auto start = std::chrono::steady_clock::now();
    PoissonStats stats;
    reconstructSequence(
        frames.size(),
        [&](size_t i) {
          const FrameImage image = readExr(frames[i].file);
          if (image.width() != first.width() || image.height() != first.height())
            throw std::invalid_argument(frames[i].file.string() + ": differs in size from " + frames[0].file.string());
          attributes = image.attributes();
          return GradientFrame::fromImage(image, frames[i].file.string());
        },
        [&](size_t i, const GradientFrame::Color& color) {
          FrameImage image(first.width(), first.height());
          for (size_t c = 0; c < 3; ++c) image.addChannel(kColorChannels[c]) = color[c];
          image.attributes() = attributes;
          image.attributes()["pathfarm.frame"] = std::to_string(frames[i].number);
          image.attributes()["pathfarm.poisson"] = description;
          writeExr(out / frames[i].file.filename(), image);
        },
        a.window, a.overlap, a.settings, &stats);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    spdlog::info("{} frames in {:.2f} s, {} CG iterations, largest relative residual {:.2e} -> {}", frames.size(),
                 seconds, stats.iterations, stats.relativeResidual, out.string());
    return kExitOk;
  });
}

}  // namespace

std::vector<Command> addPoissonCommand(CLI::App& app) {
  auto arguments = std::make_shared<PoissonArguments>();
  CLI::App* poisson = app.add_subcommand(
      "poisson", "screened Poisson reconstruction of gradient-domain frames over windows (Manzi et al. 2016)");
  poisson->add_option("dir", arguments->in, "folder of frame_NNNN.exr from render --integrator gpt|tgpt")->required();
  poisson->add_option("--window", arguments->window, "frames per window")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  poisson->add_option("--overlap", arguments->overlap, "frames shared by consecutive windows")
      ->check(CLI::Range(0, 999))
      ->capture_default_str();
  poisson->add_option("--norm", arguments->norm, "l2 (conjugate gradients) or l1 (reweighted least squares)")
      ->capture_default_str();
  poisson->add_option("--alpha", arguments->settings.alpha, "weight of the primal image")
      ->check(CLI::Range(1e-4, 1e4))
      ->capture_default_str();
  poisson->add_option("--out", arguments->out, "output folder for the reconstructed frame_NNNN.exr")->required();
  return {{poisson, [arguments] { return runPoisson(*arguments); }}};
}

}  // namespace pathfarm
