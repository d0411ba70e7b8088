// Equal-time comparison of the Metropolis integrators on an animation (issue 10,
// docs/performance.md): frame-by-frame path-space MLT, PSSMLT and temporal MLT over the
// whole frame range, with path tracing and BDPT for scale. Every method gets the same
// wall-clock budget per frame: its cost is measured by two short renders (fixed cost plus
// cost per sample or mutation per pixel), its budget solved from that line, and corrected
// once by the time the render then took. Prints a
// table of mean relMSE, temporal error (relMSE of frame-to-frame differences), brightness
// (the frames' mean luminance over the reference's, averaged over the frames) and
// brightness variation (RMS frame-to-frame change of that ratio), and writes per-frame relMSE and brightness to an SVG plot.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>

#include "bench/command_line.h"
#include "bench/bench_support.h"
#include "bench/truth_figure.h"
#include "image/exr_io.h"
#include "postproc/metrics/image_metrics.h"
#include "renderer/metropolis/metropolis_renderer.h"
#include "renderer/scene/scene_loader.h"
#include "renderer/setup/integrator_factory.h"

namespace pathfarm {
namespace {

using Sequence = std::vector<FrameImage>;

struct Frames {
  int64_t first = 0, last = 0;
  int count() const { return static_cast<int>(last - first + 1); }
};

struct Method {
  std::string name;
  std::string integrator;  // pt, bdpt, mlt, pssmlt, tmlt
};

struct Outcome {
  double budget = 0;  // samples or mutations per pixel
  double seconds = 0;
  SequenceMetrics metrics;
  bench::TruthFigure truth;  // relMSE with the reference's noise taken out
  std::vector<double> brightness;  // per frame, mean luminance over the reference's
  double brightnessVariation = 0;
};

// The whole sequence by `integrator` at `budget` samples (pt, bdpt) or mutations (the
// Metropolis methods) per pixel.
Sequence renderWith(const Scene& scene, const std::string& integrator, double budget, Frames frames,
                    RenderSettings settings) {
  Sequence out;
  if (!integratorNamed(integrator).rendersWindows) {
    settings.spp = std::max(1, static_cast<int>(std::lround(budget)));
    const auto renderer = makeFrameIntegrator(integrator, scene, settings);
    for (int64_t f = frames.first; f <= frames.last; ++f) out.push_back(renderer->render(f));
    return out;
  }
  MetropolisSettings mlt = MetropolisSettings::defaultsOf(scene);
  mlt.method = parseMetropolisMethod(integrator);
  mlt.width = settings.width;
  mlt.height = settings.height;
  mlt.maxDepth = settings.maxDepth;
  mlt.mutationsPerPixel = budget;
  const MetropolisRenderer renderer(scene, mlt);
  // Frame-by-frame MLT sees one frame at a time; the others one window over every frame.
  const int window = mlt.method == MetropolisMethod::PathSpace ? 1 : frames.count();
  for (int64_t first = frames.first; first <= frames.last; first += window)
    for (FrameImage& frame : renderer.render({first, window})) out.push_back(std::move(frame));
  return out;
}

// The budget per pixel that takes `secondsPerFrame` per frame, from the cost line through
// two short renders (fixed cost: bootstrap, geometry; and cost per unit of budget).
double equalTimeBudget(const std::function<double(double)>& secondsAt, double secondsPerFrame, int frames) {
  const double low = 1, high = 4;
  const double tLow = secondsAt(low), tHigh = secondsAt(high);
  const double perUnit = std::max(1e-9, (tHigh - tLow) / (high - low));
  const double fixed = std::max(0.0, tLow - perUnit * low);
  return std::max(1.0, (secondsPerFrame * frames - fixed) / perUnit);
}

double meanLuminance(const FrameImage& image) {
  const auto &r = image.channel("R"), &g = image.channel("G"), &b = image.channel("B");
  double sum = 0;
  for (size_t p = 0; p < r.size(); ++p) sum += 0.2126 * r[p] + 0.7152 * g[p] + 0.0722 * b[p];
  return sum / static_cast<double>(r.size());
}

// Path tracing at `spp` with another seed than the methods' (a path-traced method with the
// same seed would share its first samples with the reference).
Sequence referenceOf(const Scene& shot, Frames frames, RenderSettings settings, int spp,
                     const std::filesystem::path& folder) {
  Scene scene = shot;
  scene.seed = ~shot.seed;
  Sequence reference;
  std::filesystem::create_directories(folder);
  settings.spp = spp;
  std::unique_ptr<FrameRenderer> renderer;
  for (int64_t f = frames.first; f <= frames.last; ++f) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04ld.exr", static_cast<long>(f));
    const std::filesystem::path file = folder / name;
    if (std::filesystem::exists(file)) {
      reference.push_back(readExr(file));
      if (reference.back().width() == settings.width && reference.back().height() == settings.height) continue;
      reference.pop_back();
    }
    if (!renderer) renderer = std::make_unique<FrameRenderer>(scene, settings);
    reference.push_back(renderer->render(f));
    writeExr(file, reference.back());
  }
  return reference;
}

// Per-frame relMSE (log scale, top) and brightness over the reference (bottom), a line per method.
void writeSvg(const std::string& file, const std::vector<Method>& methods, const std::vector<Outcome>& outcomes,
              Frames frames, const std::string& caption) {
  const double left = 60, width = 520, panel = 170, top = 50, gap = 50;
  const char* colors[] = {"#4477aa", "#ee7733", "#228833", "#cc3311", "#aa3377", "#777777"};
  double low = 1e30, high = 0, bLow = 1e30, bHigh = 0;
  for (const Outcome& o : outcomes) {
    for (const ImageMetrics& m : o.metrics.frames) {
      low = std::min(low, std::max(m.relMse, 1e-6));
      high = std::max(high, m.relMse);
    }
    for (double b : o.brightness) {
      bLow = std::min(bLow, b);
      bHigh = std::max(bHigh, b);
    }
  }
  const double lo = std::floor(std::log10(low)), hi = std::max(lo + 1, std::ceil(std::log10(high)));
  bLow = std::min(bLow, 0.9);
  bHigh = std::max(bHigh, 1.1);
  const auto x = [&](size_t f) { return left + width * static_cast<double>(f) / std::max(1, frames.count() - 1); };
  const auto yError = [&](double v) { return top + panel * (hi - std::log10(std::max(v, 1e-6))) / (hi - lo); };
  const auto yBright = [&](double v) { return top + panel + gap + panel * (bHigh - v) / (bHigh - bLow); };
  std::ofstream svg(file);
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << left + width + 150 << "\" height=\""
      << top + 2 * panel + gap + 40 << "\" font-family=\"sans-serif\" font-size=\"11\">\n"
      << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n<text x=\"10\" y=\"18\" font-size=\"13\">" << caption
      << "</text>\n<text x=\"10\" y=\"" << top - 8 << "\">relMSE per frame</text>\n<text x=\"10\" y=\""
      << top + panel + gap - 8 << "\">mean luminance / reference's, per frame</text>\n";
  for (double e = lo; e <= hi; ++e)
    svg << "<line x1=\"" << left << "\" x2=\"" << left + width << "\" y1=\"" << yError(std::pow(10, e)) << "\" y2=\""
        << yError(std::pow(10, e)) << "\" stroke=\"#ddd\"/><text x=\"20\" y=\"" << yError(std::pow(10, e)) + 4
        << "\">1e" << e << "</text>\n";
  svg << "<line x1=\"" << left << "\" x2=\"" << left + width << "\" y1=\"" << yBright(1) << "\" y2=\"" << yBright(1)
      << "\" stroke=\"#999\"/><text x=\"20\" y=\"" << yBright(1) + 4 << "\">1</text>\n";
  for (size_t i = 0; i < methods.size(); ++i) {
    const char* color = colors[i % 6];
    std::ostringstream error, bright;
    for (size_t f = 0; f < outcomes[i].brightness.size(); ++f) {
      error << (f ? " L" : "M") << x(f) << ' ' << yError(outcomes[i].metrics.frames[f].relMse);
      bright << (f ? " L" : "M") << x(f) << ' ' << yBright(outcomes[i].brightness[f]);
    }
    svg << "<path d=\"" << error.str() << "\" fill=\"none\" stroke=\"" << color << "\"/>\n<path d=\"" << bright.str()
        << "\" fill=\"none\" stroke=\"" << color << "\"/>\n<text x=\"" << left + width + 10 << "\" y=\""
        << top + 14 * static_cast<double>(i) << "\" fill=\"" << color << "\">" << methods[i].name << "</text>\n";
  }
  svg << "<text x=\"" << left << "\" y=\"" << top + 2 * panel + gap + 25 << "\">frame " << frames.first
      << "</text><text x=\"" << left + width - 40 << "\" y=\"" << top + 2 * panel + gap + 25 << "\">frame "
      << frames.last << "</text>\n</svg>\n";
}

int run(const std::string& scenePath, const std::string& frameRange, int width, int height, double secondsPerFrame,
        int referenceSpp, const std::string& referenceDir, const std::string& svgFile, const std::string& methodList) {
  const Scene scene = loadScene(scenePath);
  Frames frames;
  if (std::sscanf(frameRange.c_str(), "%ld:%ld", &frames.first, &frames.last) != 2 || frames.last < frames.first)
    return 2;
  RenderSettings settings;
  settings.width = width;
  settings.height = height;
  settings.maxDepth = scene.defaults.maxDepth;
  const std::map<std::string, std::string> names = {{"pt", "PT"},
                                                    {"bdpt", "BDPT"},
                                                    {"mlt", "MLT, frame by frame"},
                                                    {"pssmlt", "PSSMLT, one window"},
                                                    {"tmlt", "TMLT, one window"}};
  std::vector<Method> methods;
  std::stringstream list(methodList);
  for (std::string integrator; std::getline(list, integrator, ',');) {
    if (!names.count(integrator)) {
      std::fprintf(stderr, "unknown method %s\n", integrator.c_str());
      return 2;
    }
    methods.push_back({names.at(integrator), integrator});
  }

  Sequence reference;
  const double referenceSeconds =
      bench::seconds([&] { reference = referenceOf(scene, frames, settings, referenceSpp, referenceDir); });
  std::printf("reference: pt at %d spp (%.0f s, cached in %s)\n", referenceSpp, referenceSeconds, referenceDir.c_str());

  std::vector<Outcome> outcomes;
  for (const Method& m : methods) {
    Outcome o;
    o.budget = equalTimeBudget(
        [&](double budget) { return bench::seconds([&] { renderWith(scene, m.integrator, budget, frames, settings); }); },
        secondsPerFrame, frames.count());
    Sequence images;
    o.seconds = bench::seconds([&] { images = renderWith(scene, m.integrator, o.budget, frames, settings); });
    // The cost line is only a model (the bootstrap, chain start-up): off by more than 10 %,
    // the budget is scaled to the time the render took and rendered again.
    const double target = secondsPerFrame * frames.count();
    if (std::abs(o.seconds / target - 1) > 0.1) {
      o.budget = std::max(1.0, o.budget * target / o.seconds);
      o.seconds = bench::seconds([&] { images = renderWith(scene, m.integrator, o.budget, frames, settings); });
    }
    o.metrics = compareSequences(images, reference, {"R", "G", "B"});
    o.truth = bench::truthFigureOf(images, reference);
    double squaredChange = 0;
    for (size_t f = 0; f < images.size(); ++f) {
      o.brightness.push_back(meanLuminance(images[f]) / std::max(1e-12, meanLuminance(reference[f])));
      if (f > 0) squaredChange += std::pow(o.brightness[f] - o.brightness[f - 1], 2);
    }
    o.brightnessVariation = images.size() > 1 ? std::sqrt(squaredChange / static_cast<double>(images.size() - 1)) : 0;
    outcomes.push_back(o);
    std::fprintf(stderr, "%s done: %.1f per pixel, %.1f s\n", m.name.c_str(), o.budget, o.seconds);
  }

  std::printf("\nthe reference's own expected relMSE (its noise): %.4f\n", outcomes.empty() ? 0.0 : outcomes[0].truth.referenceNoise);
  std::printf("\n| method | per pixel (spp or mutations) | s per frame | relMSE | against the truth (95 %%) | temporal error | "
              "brightness | brightness variation |\n| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n");
  for (size_t i = 0; i < methods.size(); ++i) {
    const Outcome& o = outcomes[i];
    double brightness = 0;
    for (double b : o.brightness) brightness += b / static_cast<double>(o.brightness.size());
    std::printf("| %s | %.1f | %.2f | %.4f | %s | %.4f | %.3f | %.4f |\n", methods[i].name.c_str(), o.budget,
                o.seconds / frames.count(), o.metrics.meanRelMse, o.truth.text().c_str(), o.metrics.temporalRelMse,
                brightness, o.brightnessVariation);
  }
  if (!svgFile.empty())
    writeSvg(svgFile, methods, outcomes, frames,
             std::filesystem::path(scenePath).parent_path().filename().string() + ": equal time, " +
                 std::to_string(width) + "x" + std::to_string(height));
  return 0;
}

}  // namespace
}  // namespace pathfarm

int main(int argc, char** argv) {
  pathfarm::bench::CommandLine app("equal-time comparison of the Metropolis integrators on an animation");
  std::string scene = "scenes/ajar_door/scene.json", frames = "0:23", referenceDir = "out/mlt-reference", svg,
              methods = "pt,bdpt,mlt,pssmlt,tmlt";
  int width = 96, height = 72, referenceSpp = 4096;
  double secondsPerFrame = 2;
  app.option("--scene", scene, "scene file");
  app.option("--frames", frames, "first:last");
  app.option("--width", width);
  app.option("--height", height);
  app.option("--seconds-per-frame", secondsPerFrame, "each method's wall-clock budget per frame");
  app.option("--reference-spp", referenceSpp, "path-traced reference samples per pixel");
  app.option("--reference-dir", referenceDir, "where the reference frames are cached");
  app.option("--svg", svg, "plot of per-frame relMSE and brightness");
  app.option("--methods", methods, "comma-separated: pt, bdpt, mlt, pssmlt, tmlt");
  if (const auto exit = app.parse(argc, argv)) return *exit;
  return app.run(
      [&] { return pathfarm::run(scene, frames, width, height, secondsPerFrame, referenceSpp, referenceDir, svg, methods); });
}
