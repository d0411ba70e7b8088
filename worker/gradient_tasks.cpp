// The tgpt pipeline's reconstruction tasks (worker/filter_tasks.h): a window of gradient
// frames solved as one screened Poisson problem, and a frame blended from its windows.
#include "image/exr_io.h"
#include "postproc/poisson/screened_poisson.h"
#include "postproc/poisson/window_blend.h"
#include "worker/failure_class.h"
#include "worker/filter_inputs.h"

namespace pathfarm::farm {
namespace {

// The reconstruction of the window's index-th frame: channels `<index>.R/G/B`.
std::string solvedChannel(size_t index, const char* channel) { return std::to_string(index) + "." + channel; }

PoissonSettings settingsOf(const ShotSpec& spec) {
  PoissonSettings settings;
  settings.norm = parsePoissonNorm(spec.poisson_norm());
  return settings;
}

}  // namespace

TaskOutput runPoissonWindowTask(const Lease& lease, std::vector<TaskInput>& inputs) {
  const int64_t first = lease.params().window_first();
  const int count = lease.params().window_frames();
  std::vector<GradientFrame> frames;
  for (int64_t frame = first; frame < first + count; ++frame)
    frames.push_back(GradientFrame::fromImage(inputOf(inputs, TASK_GRADIENT_RENDER, frame).image(),
                                              "the gradient render of frame " + std::to_string(frame)));
  std::vector<const GradientFrame*> window;
  for (const GradientFrame& frame : frames) window.push_back(&frame);
  PoissonStats stats;
  const std::vector<GradientFrame::Color> solved = reconstructWindow(window, settingsOf(lease.spec()), &stats);
  FrameImage chunk(frames.front().width, frames.front().height);
  for (size_t i = 0; i < solved.size(); ++i)
    for (size_t c = 0; c < 3; ++c) chunk.addChannel(solvedChannel(i, kColorChannels[c])) = solved[i][c];
  TaskOutput output;
  output.chunk = encodeExr(chunk, ExrCompression::Fast);
  output.metrics["cg_iterations"] = stats.iterations;
  output.metrics["relative_residual"] = stats.relativeResidual;
  return output;
}

TaskOutput runPoissonBlendTask(const Lease& lease, std::vector<TaskInput>& inputs) {
  const int64_t frame = lease.params().frame();
  const FrameImage& rendered = inputOf(inputs, TASK_GRADIENT_RENDER, frame).image();
  WindowBlend blend;
  for (const TaskInput& input : inputs) {  // in window order, as the plan lists them
    if (input.kind != TASK_POISSON_WINDOW) continue;
    const auto index = static_cast<size_t>(frame - input.params.window_first());
    GradientFrame::Color solved;
    for (size_t c = 0; c < 3; ++c) solved[c] = input.image().channel(solvedChannel(index, kColorChannels[c]));
    blend.add(solved, index, static_cast<size_t>(input.params.window_frames()));
  }
  if (blend.weight == 0) throw BadInput("no window covers frame " + std::to_string(frame));
  const GradientFrame::Color color =
      std::move(blend).finish(GradientFrame::fromImage(rendered, "the gradient render of frame " + std::to_string(frame))
                                  .directEmission);
  FrameImage image(rendered.width(), rendered.height());
  for (size_t c = 0; c < 3; ++c) image.addChannel(kColorChannels[c]) = color[c];
  image.attributes() = rendered.attributes();
  image.attributes()["pathfarm.poisson"] = lease.spec().poisson_norm() + ", window " +
                                          std::to_string(lease.spec().poisson_window()) + ", overlap " +
                                          std::to_string(lease.spec().poisson_overlap());
  TaskOutput output;
  output.chunk = encodeExr(image);
  return output;
}

}  // namespace pathfarm::farm
