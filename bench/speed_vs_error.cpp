// Speed against error of every pipeline on the demo animation (issue: the shot planner and
// the DUI pipeline). One local farm runs plain path tracing at several spp and the
// filtering pipelines d, du, di, dui; each shot's cost is its report's core-seconds per
// frame, its error the relMSE and temporal error of its frames at the evaluation frames
// against a reference rendered here. Prints a Markdown table (with the relative cost
// against pt at the baseline spp, and against pt at equal error, interpolated on the pt
// curve) and writes an SVG plot of relMSE against core-seconds per frame.
//
//   speed_vs_error [--shot scenes/cornell/shot.json] [--spp 128] [--pt-spp 32,64,...]
//                  [--reference-spp 2048] [--workers 2] [--svg FILE] [--out DIR]

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "bench/command_line.h"
#include "bench/bench_support.h"
#include "image/exr_io.h"
#include "postproc/metrics/image_metrics.h"
#include "renderer/scene/scene_loader.h"
#include "client/child_process.h"
#include "client/local_farm.h"
#include "client/shot_preparation.h"

namespace pathfarm::bench {
namespace {

struct Result {
  std::string method;
  int spp = 0;
  double coreSecondsPerFrame = 0;
  double relMse = 0;
  double temporal = 0;
  double rerenderRate = 0;
  int keyframeInterval = 1;
};

struct Options {
  std::string shot = "scenes/cornell/shot.json";
  int spp = 128;
  std::vector<int> ptSpp = {32, 64, 128, 256, 512};
  std::vector<int> duiSpp = {32, 64};
  int referenceSpp = 2048;
  int workers = 2;
  std::string out = "bench-output/speed_vs_error";
  std::string svg = "docs/figures/speed_vs_error.svg";
};

// Runs one shot on the farm; its frames go to `folder`.
Result runShot(farm::LocalFarm& farm, const farm::ShotSpec& spec, const std::filesystem::path& folder,
               const std::vector<FrameImage>& references) {
  farm::FarmClient client = farm.client();
  const int64_t id = client.submit(spec);
  const farm::ShotSummary summary = client.watch(id, [](const farm::ShotSummary&) {});
  if (summary.state() != farm::SHOT_DONE) throw std::runtime_error(spec.name() + " did not finish: " + summary.failure());
  client.fetch(id, folder);
  const farm::ShotReport report = client.report(id);
  std::vector<FrameImage> frames;
  for (const int64_t frame : spec.evaluation_frames()) frames.push_back(readExr(folder / farm::frameFileName(frame)));
  const SequenceMetrics metrics = compareSequences(frames, references, {"R", "G", "B"});
  Result result{std::string(farm::pipelineName(spec.pipeline())), spec.spp(), report.core_seconds_per_frame(), metrics.meanRelMse,
                metrics.temporalRelMse, report.rerender_rate(), report.keyframe_interval()};
  std::fprintf(stderr, "%-4s %4d spp: %.3f core-s/frame, relMSE %.5f, temporal %.5f, re-render %.1f%%\n",
               result.method.c_str(), result.spp, result.coreSecondsPerFrame, result.relMse, result.temporal,
               100 * result.rerenderRate);
  return result;
}

// Plain pt's cost at `relMse`, interpolated log-log on the pt curve (extrapolated at its ends).
double ptCostAtError(const std::vector<Result>& pt, double relMse) {
  size_t i = 1;
  while (i + 1 < pt.size() && pt[i].relMse > relMse) ++i;
  const Result &a = pt[i - 1], &b = pt[i];
  const double t = std::log(relMse / a.relMse) / std::log(b.relMse / a.relMse);
  return std::exp(std::log(a.coreSecondsPerFrame) + t * std::log(b.coreSecondsPerFrame / a.coreSecondsPerFrame));
}

void writeSvg(const std::string& file, const std::vector<Result>& pt, const std::vector<Result>& filtered) {
  const double width = 640, height = 420, left = 70, right = 20, top = 20, bottom = 50;
  double minX = 1e30, maxX = 0, minY = 1e30, maxY = 0;
  for (const auto* list : {&pt, &filtered})
    for (const Result& r : *list) {
      minX = std::min(minX, r.coreSecondsPerFrame), maxX = std::max(maxX, r.coreSecondsPerFrame);
      minY = std::min(minY, r.relMse), maxY = std::max(maxY, r.relMse);
    }
  const double x0 = std::floor(std::log10(minX)), x1 = std::ceil(std::log10(maxX));
  const double y0 = std::floor(std::log10(minY)), y1 = std::ceil(std::log10(maxY));
  const auto px = [&](double v) { return left + (std::log10(v) - x0) / (x1 - x0) * (width - left - right); };
  const auto py = [&](double v) { return top + (y1 - std::log10(v)) / (y1 - y0) * (height - top - bottom); };
  std::ofstream svg(file);
  svg << "<svg xmlns='http://www.w3.org/2000/svg' width='" << width << "' height='" << height
      << "' font-family='sans-serif' font-size='12'>\n<rect width='100%' height='100%' fill='white'/>\n";
  for (double e = x0; e <= x1; ++e)
    svg << "<line x1='" << px(std::pow(10, e)) << "' y1='" << top << "' x2='" << px(std::pow(10, e)) << "' y2='"
        << height - bottom << "' stroke='#ddd'/><text x='" << px(std::pow(10, e)) << "' y='" << height - bottom + 16
        << "' text-anchor='middle'>1e" << e << "</text>\n";
  for (double e = y0; e <= y1; ++e)
    svg << "<line x1='" << left << "' y1='" << py(std::pow(10, e)) << "' x2='" << width - right << "' y2='"
        << py(std::pow(10, e)) << "' stroke='#ddd'/><text x='" << left - 6 << "' y='" << py(std::pow(10, e)) + 4
        << "' text-anchor='end'>1e" << e << "</text>\n";
  svg << "<text x='" << (left + width - right) / 2 << "' y='" << height - 12
      << "' text-anchor='middle'>core-seconds per frame (log)</text>\n<text x='16' y='" << (top + height - bottom) / 2
      << "' transform='rotate(-90 16 " << (top + height - bottom) / 2 << ")' text-anchor='middle'>relMSE (log)</text>\n";
  svg << "<polyline fill='none' stroke='#444' stroke-width='1.5' points='";
  for (const Result& r : pt) svg << px(r.coreSecondsPerFrame) << "," << py(r.relMse) << " ";
  svg << "'/>\n";
  for (const Result& r : pt)
    svg << "<circle cx='" << px(r.coreSecondsPerFrame) << "' cy='" << py(r.relMse) << "' r='3' fill='#444'/><text x='"
        << px(r.coreSecondsPerFrame) + 5 << "' y='" << py(r.relMse) - 5 << "'>pt " << r.spp << "</text>\n";
  const std::map<std::string, std::string> colors = {{"d", "#1f77b4"}, {"du", "#2ca02c"}, {"di", "#ff7f0e"}, {"dui", "#d62728"}};
  for (const Result& r : filtered)
    svg << "<rect x='" << px(r.coreSecondsPerFrame) - 4 << "' y='" << py(r.relMse) - 4 << "' width='8' height='8' fill='"
        << colors.at(r.method) << "'/><text x='" << px(r.coreSecondsPerFrame) + 6 << "' y='" << py(r.relMse) + 14
        << "' fill='" << colors.at(r.method) << "'>" << r.method << " " << r.spp << "</text>\n";
  svg << "</svg>\n";
}

int run(const Options& options) {
  farm::ShotSpec base = farm::loadShotFile(options.shot);
  const Scene scene = loadScene(base.scene());
  const std::vector<int64_t> evaluation(base.evaluation_frames().begin(), base.evaluation_frames().end());
  std::fprintf(stderr, "%s: frames %lld..%lld at %dx%d, evaluation frames %lld and %lld, keyframes: %s\n",
               base.name().c_str(), static_cast<long long>(base.frame_start()),
               static_cast<long long>(base.frame_end()), base.width(), base.height(),
               static_cast<long long>(evaluation.front()), static_cast<long long>(evaluation.back()),
               base.keyframe_reason().c_str());
  // The reference is kept next to the results and reused while its settings hold. Its
  // samples are independent of the shots' ("-independent": one kept by an older version
  // drew the shots' own samples and is not reused).
  const std::filesystem::path out(options.out);
  const std::filesystem::path referenceFolder =
      out / ("reference-" + std::to_string(options.referenceSpp) + "-independent");
  std::filesystem::create_directories(referenceFolder);
  std::vector<FrameImage> references;
  const double referenceSeconds = seconds([&] {
    for (const int64_t frame : evaluation) {
      const std::filesystem::path file = referenceFolder / farm::frameFileName(frame);
      if (!std::filesystem::exists(file))
        writeExr(file, render(scene, base.width(), base.height(), options.referenceSpp, frame, false, kIndependentFirstSample));
      references.push_back(readExr(file));
    }
  });
  std::fprintf(stderr, "reference: %d spp, %.1f s (%s)\n", options.referenceSpp, referenceSeconds,
               referenceFolder.c_str());
  for (const auto& entry : std::filesystem::directory_iterator(out))
    if (entry.path().filename().string().rfind("reference-", 0) != 0) std::filesystem::remove_all(entry.path());
  const std::filesystem::path bin = std::filesystem::path(farm::currentExecutable()).parent_path();
  farm::LocalFarmOptions farmOptions;
  farmOptions.folder = out / "farm";
  farmOptions.workers = options.workers;
  farmOptions.threadsPerWorker = 1;
  farmOptions.executable = (bin / "pathfarm").string();
  farm::LocalFarm farm(farmOptions);

  // Plain pt on the evaluation frames only: its cost per frame does not depend on which.
  std::vector<Result> pt;
  for (const int spp : options.ptSpp) {
    farm::ShotSpec spec = base;
    spec.set_name("pt-" + std::to_string(spp));
    spec.set_pipeline(farm::PIPELINE_PT);
    spec.set_decompose("none");
    spec.set_spp(spp);
    spec.set_frame_start(evaluation.front());
    spec.set_frame_end(evaluation.back());
    spec.set_reference_spp(0);
    pt.push_back(runShot(farm, spec, out / spec.name(), references));
  }
  const auto baseline = std::find_if(pt.begin(), pt.end(), [&](const Result& r) { return r.spp == options.spp; });
  if (baseline == pt.end()) throw std::runtime_error("--pt-spp must include the baseline --spp");

  std::vector<std::pair<farm::Pipeline, int>> runs = {
      {farm::PIPELINE_D, options.spp}, {farm::PIPELINE_DU, options.spp}, {farm::PIPELINE_DI, options.spp},
      {farm::PIPELINE_DUI, options.spp}};
  for (const int spp : options.duiSpp) runs.emplace_back(farm::PIPELINE_DUI, spp);
  std::vector<Result> filtered;
  for (const auto& [pipeline, spp] : runs) {
    farm::ShotSpec spec = base;
    spec.set_name(std::string(farm::pipelineName(pipeline)) + "-" + std::to_string(spp));
    spec.set_pipeline(pipeline);
    spec.set_spp(spp);
    spec.set_reference_spp(0);
    spec.set_baseline_core_seconds(baseline->coreSecondsPerFrame);  // measured above; not again
    if (!farm::stagesOf(pipeline).interpolate) spec.set_keyframe_interval(1);
    filtered.push_back(runShot(farm, spec, out / spec.name(), references));
  }
  farm.stop();

  std::printf("| method | spp | k | core-s / frame | relMSE | temporal error | re-render | relative cost vs pt %d | pt core-s at equal relMSE | relative cost at equal relMSE |\n",
              options.spp);
  std::printf("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n");
  for (const Result& r : pt)
    std::printf("| pt | %d | 1 | %.3f | %.5f | %.5f | | %.3f | | |\n", r.spp, r.coreSecondsPerFrame, r.relMse, r.temporal,
                r.coreSecondsPerFrame / baseline->coreSecondsPerFrame);
  for (const Result& r : filtered) {
    const double equal = ptCostAtError(pt, r.relMse);
    std::printf("| %s | %d | %d | %.3f | %.5f | %.5f | %.1f%% | %.3f | %.3f | %.3f |\n", r.method.c_str(), r.spp,
                r.keyframeInterval, r.coreSecondsPerFrame, r.relMse, r.temporal, 100 * r.rerenderRate,
                r.coreSecondsPerFrame / baseline->coreSecondsPerFrame, equal, r.coreSecondsPerFrame / equal);
  }
  writeSvg(options.svg, pt, filtered);
  std::fprintf(stderr, "plot: %s\n", options.svg.c_str());
  return 0;
}

}  // namespace
}  // namespace pathfarm::bench

int main(int argc, char** argv) {
  pathfarm::bench::Options options;
  pathfarm::bench::CommandLine app("speed against error of pt and the filtering pipelines on a shot");
  app.option("--shot", options.shot, "the shot (its scene, frames, resolution, evaluation frames)");
  app.option("--spp", options.spp, "the baseline spp: d, du, di, dui run at it");
  app.option("--pt-spp", options.ptSpp, "plain pt sample counts (ascending, with --spp)").commaSeparated();
  app.option("--dui-spp", options.duiSpp, "further dui sample counts").commaSeparated();
  app.option("--reference-spp", options.referenceSpp, "samples of the reference");
  app.option("--workers", options.workers, "worker processes (one thread each)");
  app.option("--out", options.out, "where the farm and the frames go");
  app.option("--svg", options.svg, "the plot");
  if (const auto exit = app.parse(argc, argv)) return *exit;
  return app.run([&] { return pathfarm::bench::run(options); });
}
