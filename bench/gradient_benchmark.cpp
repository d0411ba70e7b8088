// Gradient-domain rendering (Manzi et al. 2016) on this machine: what the screened
// Poisson reconstruction costs, and what PT, GPT and TGPT buy at equal time.
//
//   build/bin/gradient_benchmark reconstruction --norm l2|l1 [--input DIR] [--res 1280x720] [--frames 10]
//        [--repeat 1] [--irls-rounds 10] [--irls-iterations 15] [--irls-start-epsilon 0.1]
//        [--irls-epsilon 0.001] [--save FILE] [--compare FILE]
//   build/bin/gradient_benchmark equal-time [--scene scenes/cornell/scene.json] [--frames 0:23]
//        [--res 128x128] [--pt-spp 16] [--reference-spp 512] [--reference-dir DIR]
//        [--svg docs/figures/gradient_equal_time.svg]
//
// `reconstruction` solves one window of frames, read from DIR's first frame_NNNN.exr files
// (a `pathfarm render --integrator tgpt` output) or, without DIR, a synthetic window (a
// smooth image with noisy primal, spatial, temporal and mixed differences), and prints the
// seconds of the solve and the process's peak resident memory (getrusage), then the
// objective the norm minimizes at the solution. Run one norm per process: the peak is the
// process's. --repeat N solves N times and prints the median seconds; the --irls options
// change the L1 schedule (a start epsilon equal to the last keeps epsilon fixed). --save FILE keeps the reconstruction (raw floats); --compare FILE prints its
// relative difference to one saved before (another solver's, say).
//
// `equal-time` first measures each method's cost per sample per pixel on one frame, gives
// every method the samples that take at most as long as --pt-spp path-traced samples, renders the
// frames, reconstructs, and prints relMSE and temporal error against a path-traced
// reference as a Markdown table; with --svg it also writes the table as a bar chart.
#include <sys/resource.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <regex>

#include "bench/command_line.h"
#include "bench/bench_support.h"
#include "bench/median.h"
#include "bench/truth_figure.h"
#include "image/exr_io.h"
#include "postproc/metrics/relmse.h"
#include "postproc/poisson/poisson_system.h"
#include "postproc/poisson/window_blend.h"
#include "renderer/scene/scene_loader.h"
#include "renderer/setup/integrator_factory.h"

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
  if (!std::filesystem::is_directory(folder)) throw std::runtime_error(folder.string() + ": not a folder");
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

// The objective of Section 5 at the reconstruction: the sum over rows of |residual|^p
// times alpha^p for the data rows, per channel summed. Absent rows have residual 0.
double objective(const std::vector<const GradientFrame*>& window, const std::vector<GradientFrame::Color>& solved,
                 const PoissonSettings& settings) {
  const PoissonSystem system(window, settings.alpha);
  const size_t pixels = window[0]->pixelCount();
  std::vector<float> x(system.size());
  for (size_t f = 0; f < solved.size(); ++f)
    for (size_t c = 0; c < 3; ++c)
      for (size_t p = 0; p < pixels; ++p) x[3 * (f * pixels + p) + c] = solved[f][c][p];
  const auto residuals = system.residuals(x);
  double sum = 0;
  for (size_t k = 0; k < PoissonSystem::kBlocks; ++k) {
    const double scale = k == PoissonSystem::Data ? settings.alpha : 1.0;
    for (float r : residuals[k]) {
      const double v = scale * std::abs(static_cast<double>(r));
      sum += settings.norm == PoissonNorm::L1 ? v : v * v;
    }
  }
  return sum;
}

// The reconstruction as raw floats, frame by frame, channel by channel.
void saveRaw(const std::string& file, const std::vector<GradientFrame::Color>& solved) {
  std::ofstream out(file, std::ios::binary);
  for (const auto& frame : solved)
    for (const auto& plane : frame)
      out.write(reinterpret_cast<const char*>(plane.data()), static_cast<std::streamsize>(plane.size() * sizeof(float)));
  if (!out) throw std::runtime_error(file + ": cannot write");
}

// RMS and largest |a - b| over every value, relative to the RMS of the saved `file`.
void compareRaw(const std::string& file, const std::vector<GradientFrame::Color>& solved) {
  std::ifstream in(file, std::ios::binary);
  double squares = 0, reference = 0, largest = 0;
  size_t count = 0;
  for (const auto& frame : solved)
    for (const auto& plane : frame) {
      std::vector<float> saved(plane.size());
      in.read(reinterpret_cast<char*>(saved.data()), static_cast<std::streamsize>(saved.size() * sizeof(float)));
      if (!in) throw std::runtime_error(file + ": not a reconstruction of this window");
      for (size_t i = 0; i < plane.size(); ++i) {
        const double d = static_cast<double>(plane[i]) - saved[i];
        squares += d * d;
        reference += static_cast<double>(saved[i]) * saved[i];
        largest = std::max(largest, std::abs(d));
        ++count;
      }
    }
  const double rms = std::sqrt(reference / static_cast<double>(count));
  std::printf("against %s: RMS difference %.2e, largest %.2e, relative to the saved RMS %.3f\n", file.c_str(),
              std::sqrt(squares / static_cast<double>(count)) / rms, largest / rms, rms);
}

int reconstruction(const std::string& norm, const std::string& input, int width, int height, int frames,
                   int repeat, PoissonSettings settings, const std::string& saveFile, const std::string& compareFile) {
  const std::vector<GradientFrame> window =
      input.empty() ? syntheticWindow(width, height, frames) : windowFrom(input, frames);
  std::vector<const GradientFrame*> pointers;
  for (const GradientFrame& f : window) pointers.push_back(&f);
  settings.norm = parsePoissonNorm(norm);
  PoissonStats stats;
  std::vector<GradientFrame::Color> solved;
  std::vector<double> wall, cpu;
  for (int run = 0; run < repeat; ++run) {
    solved.clear();  // the peak memory is one solve's
    const double cpuBefore = cpuSeconds(usageNow());
    wall.push_back(bench::seconds([&] { solved = reconstructWindow(pointers, settings, &stats); }));
    cpu.push_back(cpuSeconds(usageNow()) - cpuBefore);
    if (repeat > 1) std::printf("run %d: %.2f s (%.2f CPU s)\n", run + 1, wall.back(), cpu.back());
  }
  // ru_maxrss is in KiB.
  std::printf(
      "%s, %zu frames of %dx%d (%s): %.2f s (%.2f CPU s)%s, %d CG iterations (all channels), relative "
      "residual %.1e, peak resident memory %.2f GiB\n",
      norm.c_str(), window.size(), window[0].width, window[0].height, input.empty() ? "synthetic" : input.c_str(),
      bench::median(wall), bench::median(cpu), repeat > 1 ? " (medians)" : "", stats.iterations,
      stats.relativeResidual, static_cast<double>(usageNow().ru_maxrss) / (1024.0 * 1024.0));
  std::printf("objective (%s norm): %.6e\n", norm.c_str(), objective(pointers, solved, settings));
  if (!saveFile.empty()) saveRaw(saveFile, solved);
  if (!compareFile.empty()) compareRaw(compareFile, solved);
  return 0;
}

// One way of spending the same render time, and how its frames are reconstructed.
struct Method {
  std::string name;
  std::string integrator;  // pt, gpt, tgpt
  bool motion = true;
  int batches = 1;
  PoissonNorm norm = PoissonNorm::L2;
  size_t window = 1, overlap = 0;
};

struct Outcome {
  int spp = 0;
  double costRatio = 1;  // seconds per sample per pixel, relative to PT
  double renderSeconds = 0, reconstructSeconds = 0, relMse = 0, temporalError = 0;
  bench::TruthFigure truth;  // relMSE with the reference's noise taken out
};

using Sequence = std::vector<FrameImage>;

// Mean over consecutive frames of the relative squared error of the frame-to-frame change
// against the reference's change: flicker the reference does not have.
double temporalError(const Sequence& frames, const Sequence& reference) {
  double sum = 0;
  size_t count = 0;
  for (size_t f = 0; f + 1 < frames.size(); ++f)
    for (const char* c : {"R", "G", "B"}) {
      const auto &a0 = frames[f].channel(c), &a1 = frames[f + 1].channel(c);
      const auto &r0 = reference[f].channel(c), &r1 = reference[f + 1].channel(c);
      for (size_t p = 0; p < a0.size(); ++p) {
        const double change = (a1[p] - a0[p]) - (r1[p] - r0[p]);
        sum += change * change / (static_cast<double>(r0[p]) * r0[p] + 0.01);
        ++count;
      }
    }
  return count ? sum / static_cast<double>(count) : 0;
}

Sequence renderSequence(const Scene& scene, RenderSettings settings, const Method& m, int64_t first, int64_t last,
                        double* seconds) {
  Sequence frames;
  *seconds = bench::seconds([&] {
    const auto renderer = makeFrameIntegrator(m.integrator, scene, settings, {.motionVectors = m.motion, .batches = m.batches});
    for (int64_t f = first; f <= last; ++f) frames.push_back(renderer->render(f));
  });
  return frames;
}

Sequence reconstructSequenceOf(const Sequence& rendered, const Method& m, double* seconds) {
  Sequence out(rendered.size());
  PoissonSettings settings;
  settings.norm = m.norm;
  *seconds = bench::seconds([&] {
    reconstructSequence(
        rendered.size(), [&](size_t f) { return GradientFrame::fromImage(rendered[f], "frame"); },
        [&](size_t f, const GradientFrame::Color& color) {
          out[f] = FrameImage(rendered[f].width(), rendered[f].height());
          for (size_t c = 0; c < 3; ++c) out[f].addChannel(kColorChannels[c]) = color[c];
        },
        m.window, m.overlap, settings);
  });
  return out;
}

// The table as grouped bars, relMSE and temporal error side by side, on a log scale.
void writeSvg(const std::string& file, const std::vector<Method>& methods, const std::vector<Outcome>& outcomes,
              const std::string& caption) {
  const double left = 210, barHeight = 9, rowHeight = 26, top = 50, width = 360;
  double low = 1e30, high = 0;
  for (const Outcome& o : outcomes)
    for (double v : {o.relMse, o.temporalError}) {
      low = std::min(low, v);
      high = std::max(high, v);
    }
  const double lo = std::floor(std::log10(low)), hi = std::ceil(std::log10(high));
  const auto x = [&](double v) { return left + width * (std::log10(v) - lo) / (hi - lo); };
  std::ofstream svg(file);
  const double height = top + rowHeight * static_cast<double>(methods.size()) + 40;
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << left + width + 30 << "\" height=\"" << height
      << "\" font-family=\"sans-serif\" font-size=\"11\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
      << "<text x=\"10\" y=\"18\" font-size=\"13\">" << caption << "</text>\n"
      << "<rect x=\"" << left << "\" y=\"28\" width=\"10\" height=\"8\" fill=\"#4477aa\"/><text x=\"" << left + 14
      << "\" y=\"36\">relMSE</text><rect x=\"" << left + 80
      << "\" y=\"28\" width=\"10\" height=\"8\" fill=\"#ee7733\"/>"
      << "<text x=\"" << left + 94 << "\" y=\"36\">temporal error</text>\n";
  for (double e = lo; e <= hi; ++e) {
    svg << "<line x1=\"" << x(std::pow(10, e)) << "\" y1=\"" << top - 5 << "\" x2=\"" << x(std::pow(10, e))
        << "\" y2=\"" << height - 30 << "\" stroke=\"#ccc\"/><text x=\"" << x(std::pow(10, e)) - 12 << "\" y=\""
        << height - 16 << "\">1e" << e << "</text>\n";
  }
  for (size_t i = 0; i < methods.size(); ++i) {
    const double y = top + rowHeight * static_cast<double>(i);
    svg << "<text x=\"10\" y=\"" << y + 2 * barHeight - 2 << "\">" << methods[i].name << "</text>\n";
    svg << "<rect x=\"" << left << "\" y=\"" << y << "\" width=\"" << x(outcomes[i].relMse) - left << "\" height=\""
        << barHeight << "\" fill=\"#4477aa\"/>\n";
    svg << "<rect x=\"" << left << "\" y=\"" << y + barHeight << "\" width=\"" << x(outcomes[i].temporalError) - left
        << "\" height=\"" << barHeight << "\" fill=\"#ee7733\"/>\n";
  }
  svg << "</svg>\n";
}

int equalTime(const std::string& scenePath, const std::string& frames, int width, int height, int ptSpp,
              int referenceSpp, const std::string& referenceDir, const std::string& svgFile) {
  const Scene scene = loadScene(scenePath);
  int64_t first = 0, last = 0;
  if (std::sscanf(frames.c_str(), "%ld:%ld", &first, &last) != 2 || last < first) return 2;
  RenderSettings settings;
  settings.width = width;
  settings.height = height;
  settings.maxDepth = scene.defaults.maxDepth;
  const std::vector<Method> methods{
      {"PT", "pt"},
      {"GPT, L2", "gpt"},
      {"GPT, L1", "gpt", true, 1, PoissonNorm::L1},
      {"TGPT, L2", "tgpt", true, 1, PoissonNorm::L2, 10, 5},
      {"TGPT, L1", "tgpt", true, 1, PoissonNorm::L1, 10, 5},
      {"TGPT, L1, no motion vectors", "tgpt", false, 1, PoissonNorm::L1, 10, 5},
      {"TGPT, L2, adaptive", "tgpt", true, 4, PoissonNorm::L2, 10, 5},
      {"TGPT, L1, adaptive", "tgpt", true, 4, PoissonNorm::L1, 10, 5},
  };

  // Cost per sample per pixel of each way of rendering (motion vectors or not cost the
  // same), the median of three renders of the middle frame.
  const auto costKey = [](const Method& m) { return m.integrator + (m.batches > 1 ? "-adaptive" : ""); };
  const int64_t middle = (first + last) / 2;
  std::map<std::string, double> cost;
  for (const Method& m : methods) {
    if (cost.count(costKey(m))) continue;
    RenderSettings calibration = settings;
    calibration.spp = 8;
    std::vector<double> runs(3);
    for (double& seconds : runs) renderSequence(scene, calibration, m, middle, middle, &seconds);
    cost[costKey(m)] = bench::median(runs) / 8;
  }
  Sequence truth;
  if (!referenceDir.empty() && std::filesystem::exists(referenceDir)) {
    for (int64_t f = first; f <= last; ++f)
      truth.push_back(readExr(std::filesystem::path(referenceDir) / ("frame_" + std::to_string(f) + ".exr")));
    std::printf("reference: read from %s\n", referenceDir.c_str());
  } else {
    RenderSettings reference = settings;
    reference.spp = referenceSpp;
    reference.firstSample = kIndependentFirstSample;  // shares no sample with the renders it judges
    double referenceSeconds = 0;
    truth = renderSequence(scene, reference, methods[0], first, last, &referenceSeconds);
    std::printf("reference: %d spp, %.1f s\n", referenceSpp, referenceSeconds);
    if (!referenceDir.empty()) {
      std::filesystem::create_directories(referenceDir);
      for (int64_t f = first; f <= last; ++f)
        writeExr(std::filesystem::path(referenceDir) / ("frame_" + std::to_string(f) + ".exr"),
                 truth[static_cast<size_t>(f - first)]);
    }
  }

  std::vector<Outcome> outcomes;
  std::map<std::string, std::pair<Sequence, Outcome>> renders;  // shared by methods that differ in norm only
  for (const Method& m : methods) {
    const std::string key = costKey(m) + (m.motion ? "" : "-still");
    if (!renders.count(key)) {
      Outcome o;
      o.costRatio = cost[costKey(m)] / cost["pt"];
      // Never more time than PT's: the samples are rounded down.
      o.spp = std::max(m.batches, static_cast<int>(std::floor(ptSpp / o.costRatio)));
      RenderSettings s = settings;
      s.spp = o.spp;
      Sequence frames = renderSequence(scene, s, m, first, last, &o.renderSeconds);
      renders[key] = {std::move(frames), o};
    }
    const auto& [rendered, base] = renders[key];
    Outcome o = base;
    const Sequence result = m.integrator == "pt" ? rendered : reconstructSequenceOf(rendered, m, &o.reconstructSeconds);
    for (size_t f = 0; f < result.size(); ++f)
      o.relMse += relMse(result[f], truth[f]) / static_cast<double>(result.size());
    o.temporalError = temporalError(result, truth);
    o.truth = bench::truthFigureOf(result, truth);
    outcomes.push_back(o);
  }

  std::printf("\n%s, frames %ld..%ld at %dx%d, equal render time with PT at %d spp\n\n", scenePath.c_str(), first, last,
              width, height, ptSpp);
  std::printf("the reference's own expected relMSE (its noise): %.4f\n\n", outcomes.empty() ? 0.0 : outcomes[0].truth.referenceNoise);
  std::printf("| method | cost per sample (PT = 1) | spp | render s | reconstruction s | relMSE | against the truth (95 %%) | "
              "temporal error |\n");
  std::printf("| --- | --- | --- | --- | --- | --- | --- | --- |\n");
  for (size_t i = 0; i < methods.size(); ++i) {
    const Outcome& o = outcomes[i];
    std::printf("| %s | %.2f | %d | %.1f | %.1f | %.4f | %s | %.4f |\n", methods[i].name.c_str(), o.costRatio, o.spp,
                o.renderSeconds, o.reconstructSeconds, o.relMse, o.truth.text().c_str(), o.temporalError);
  }
  if (!svgFile.empty()) {
    char caption[200];
    std::snprintf(caption, sizeof caption, "Equal render time (PT %d spp), %dx%d, frames %ld-%ld", ptSpp, width, height,
                  first, last);
    writeSvg(svgFile, methods, outcomes, caption);
    std::printf("\nplot: %s\n", svgFile.c_str());
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  bench::CommandLine app("pathfarm gradient-domain benchmark");
  std::string norm = "l2", input, resolution = "1280x720";
  int frames = 10, repeat = 1;
  bench::CommandLine& solve = app.subcommand("reconstruction", "seconds and peak memory of one window's reconstruction");
  solve.option("--norm", norm);
  solve.option("--input", input, "folder of frame_NNNN.exr from render --integrator tgpt");
  solve.option("--res", resolution);
  solve.option("--frames", frames);
  solve.option("--repeat", repeat, "solves this many times; prints the medians").positive();
  PoissonSettings poisson;
  solve.option("--irls-rounds", poisson.irlsRounds, "L1: rounds, the first being the L2 solve");
  solve.option("--irls-iterations", poisson.irlsIterations, "L1: CG iterations per round");
  solve.option("--irls-start-epsilon", poisson.irlsStartEpsilon, "L1: epsilon of the first reweighted round");
  solve.option("--irls-epsilon", poisson.irlsEpsilon, "L1: epsilon of the last round");
  std::string saveFile, compareFile;
  solve.option("--save", saveFile, "writes the reconstruction here (raw floats)");
  solve.option("--compare", compareFile, "a reconstruction saved with --save to compare with");
  std::string scene = "scenes/cornell/scene.json", range = "0:23", svg, equalResolution = "128x128";
  int ptSpp = 16, referenceSpp = 1024;
  bench::CommandLine& compare = app.subcommand("equal-time", "PT, GPT and TGPT at equal render time");
  compare.option("--scene", scene);
  compare.option("--frames", range);
  compare.option("--res", equalResolution);
  compare.option("--pt-spp", ptSpp);
  compare.option("--reference-spp", referenceSpp);
  compare.option("--svg", svg);
  std::string referenceDir;
  compare.option("--reference-dir", referenceDir, "keeps the reference frames here and reuses them");
  if (const auto exit = app.parse(argc, argv)) return *exit;
  int width = 0, height = 0;
  if (std::sscanf((solve.given() ? resolution : equalResolution).c_str(), "%dx%d", &width, &height) != 2) return 2;
  return app.run([&] {
    if (solve.given()) return reconstruction(norm, input, width, height, frames, repeat, poisson, saveFile, compareFile);
    return equalTime(scene, range, width, height, ptSpp, referenceSpp, referenceDir, svg);
  });
}
