// Gradient-domain rendering (Manzi et al. 2016) on this machine: what the screened
// Poisson reconstruction costs, and what PT, GPT and TGPT buy at equal time.
//
//   build/bin/gradient_benchmark reconstruction --norm l2|l1 [--input DIR] [--res 1280x720] [--frames 10]
//   build/bin/gradient_benchmark equal-time [--scene scenes/cornell/scene.json] [--frames 0:23]
//        [--res 128x128] [--pt-spp 16] [--reference-spp 512] [--svg docs/figures/gradient_equal_time.svg]
//
// `reconstruction` solves one window of frames, read from DIR's first frame_NNNN.exr files
// (a `pathfarm render --integrator tgpt` output) or, without DIR, a synthetic window (a
// smooth image with noisy primal, spatial, temporal and mixed differences), and prints the
// seconds of the solve and the process's peak resident memory (getrusage). Run one norm
// per process: the peak is the process's.
//
// `equal-time` first measures each method's cost per sample per pixel on one frame, gives
// every method the samples that take as long as --pt-spp path-traced samples, renders the
// frames, reconstructs, and prints relMSE and temporal error against a path-traced
// reference as a Markdown table; with --svg it also writes the table as a bar chart.
#include <sys/resource.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <regex>

#include "bench/bench_support.h"
#include "image/exr_io.h"
#include "postproc/metrics/relmse.h"
#include "postproc/poisson/window_blend.h"
#include "renderer/integrators/gradient_frame_renderer.h"
#include "renderer/scene/scene_loader.h"

namespace {

using namespace pathfarm;

rusage usageNow() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage;
}

double cpuSeconds(const rusage& u) {
  const auto s = [](const timeval& t) { return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec); };
  return s(u.ru_utime) + s(u.ru_stime);
}

// A smooth moving image with noisy measurements of everything the solver reads.
std::vector<GradientFrame> syntheticWindow(int w, int h, int frames) {
  const auto clean = [](int c, int x, int y, int f) {
    return 0.5f + 0.3f * std::sin(0.02f * static_cast<float>(x + 3 * f) + static_cast<float>(c)) *
                      std::cos(0.03f * static_cast<float>(y));
  };
  const auto noise = [](uint32_t seed, size_t i) {
    uint32_t v = seed * 0x9E3779B9u ^ static_cast<uint32_t>(i) * 0x85EBCA6Bu;
    v ^= v >> 15;
    v *= 0x2C1B3C6Du;
    v ^= v >> 12;
    return 0.1f * (static_cast<float>(v >> 8) / 16777216.0f - 0.5f);
  };
  std::vector<GradientFrame> window(static_cast<size_t>(frames));
  for (int f = 0; f < frames; ++f) {
    GradientFrame& g = window[static_cast<size_t>(f)];
    g.width = w;
    g.height = h;
    const size_t n = g.pixelCount();
    g.temporalTarget.assign(n, -1);
    for (auto* layer : {&g.primal, &g.gradientX, &g.gradientY, &g.directEmission, &g.temporal, &g.mixedX, &g.mixedY})
      for (auto& plane : *layer) plane.assign(n, 0.0f);
    for (int c = 0; c < 3; ++c)
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          const size_t p = static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x);
          const auto i = static_cast<size_t>(c);
          const uint32_t seed = static_cast<uint32_t>(f * 16 + c * 4);
          g.primal[i][p] = clean(c, x, y, f) + 4 * noise(seed, p);
          if (x + 1 < w) g.gradientX[i][p] = clean(c, x + 1, y, f) - clean(c, x, y, f) + noise(seed + 1, p);
          if (y + 1 < h) g.gradientY[i][p] = clean(c, x, y + 1, f) - clean(c, x, y, f) + noise(seed + 2, p);
          // The image moves 3 pixels left per frame: pixel x meets x - 3 in the next frame.
          if (x >= 3) {
            g.temporalTarget[p] = static_cast<int32_t>(p - 3);
            g.temporal[i][p] = clean(c, x - 3, y, f + 1) - clean(c, x, y, f) + noise(seed + 3, p);
            g.mixedX[i][p] = noise(seed + 1, p);
            g.mixedY[i][p] = noise(seed + 2, p);
          }
        }
  }
  return window;
}

std::vector<GradientFrame> windowFrom(const std::filesystem::path& folder, int frames) {
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(folder))
    if (std::regex_match(entry.path().filename().string(), std::regex("frame_[0-9]+\\.exr")))
      files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  if (files.size() < static_cast<size_t>(frames)) throw std::runtime_error(folder.string() + ": too few frames");
  std::vector<GradientFrame> window;
  for (int f = 0; f < frames; ++f)
    window.push_back(GradientFrame::fromImage(readExr(files[static_cast<size_t>(f)]), files[static_cast<size_t>(f)]));
  return window;
}

int reconstruction(const std::string& norm, const std::string& input, int width, int height, int frames) {
  const std::vector<GradientFrame> window =
      input.empty() ? syntheticWindow(width, height, frames) : windowFrom(input, frames);
  std::vector<const GradientFrame*> pointers;
  for (const GradientFrame& f : window) pointers.push_back(&f);
  PoissonSettings settings;
  settings.norm = parsePoissonNorm(norm);
  PoissonStats stats;
  const double cpuBefore = cpuSeconds(usageNow());
  const double seconds = bench::seconds([&] { reconstructWindow(pointers, settings, &stats); });
  const rusage after = usageNow();
  // ru_maxrss is in KiB.
  std::printf("%s, %zu frames of %dx%d (%s): %.2f s (%.2f CPU s), %d CG iterations (all channels), relative "
              "residual %.1e, peak resident memory %.2f GiB\n",
              norm.c_str(), window.size(), window[0].width, window[0].height, input.empty() ? "synthetic" : input.c_str(),
              seconds, cpuSeconds(after) - cpuBefore, stats.iterations, stats.relativeResidual,
              static_cast<double>(after.ru_maxrss) / (1024.0 * 1024.0));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"pathfarm gradient-domain benchmark"};
  app.require_subcommand(1);
  std::string norm = "l2", input, resolution = "1280x720";
  int frames = 10;
  CLI::App* solve = app.add_subcommand("reconstruction", "seconds and peak memory of one window's reconstruction");
  solve->add_option("--norm", norm);
  solve->add_option("--input", input, "folder of frame_NNNN.exr from render --integrator tgpt");
  solve->add_option("--res", resolution);
  solve->add_option("--frames", frames);
  CLI11_PARSE(app, argc, argv);
  int width = 0, height = 0;
  if (std::sscanf(resolution.c_str(), "%dx%d", &width, &height) != 2) return 2;
  if (solve->parsed()) return reconstruction(norm, input, width, height, frames);
  return 2;
}
