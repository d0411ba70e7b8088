#include "worker/task_runner.h"

#include <tbb/task_arena.h>

#include <algorithm>
#include <map>

#include "contract/pipeline.h"
#include "image/atomic_file.h"
#include "image/exr_io.h"
#include "image/size_text.h"
#include "renderer/integrators/frame_renderer.h"
#include "renderer/integrators/gradient_estimates.h"
#include "renderer/scene/scene_loader.h"
#include "renderer/setup/auto_decomposition.h"
#include "worker/chunk_channels.h"
#include "renderer/setup/integrator_factory.h"
#include "worker/failure_class.h"
#include "worker/filter_inputs.h"
#include "worker/metropolis_tasks.h"
#include "worker/scene_files.h"

namespace pathfarm::farm {
namespace {

constexpr size_t kShotsKept = 2;

RenderSettings settingsOf(const Scene& scene, const ShotSpec& spec, int threads) {
  RenderSettings settings;
  settings.decomposition = decompositionFor(scene, spec.decompose().empty() ? "none" : spec.decompose());
  settings.width = spec.width();
  settings.height = spec.height();
  settings.spp = spec.spp();
  settings.maxDepth = spec.max_depth();
  settings.firstSample = spec.first_sample();
  settings.threads = threads;
  // Small internal tiles: progress (each finished one) reaches the scheduler often enough
  // that a slow farm tile is never mistaken for a hung one. The bits do not depend on it.
  settings.tileSize = 8;
  return settings;
}

// A render's progress callback: reports to `progress`, stops with TaskAbandoned once
// `abandon` is set.
// A decoded input chunk's values must be finite: a damaged chunk is the shot's bad input.
void requireFinite(const FrameImage& frame, const ChunkRef& ref) {
  if (const std::string bad = frame.firstNonFinite(); !bad.empty())
    throw BadInput("input chunk " + ref.sha256() + " holds a non-finite value (" + bad + ")");
}

ProgressCallback abandonable(std::atomic<double>& progress, const std::atomic<bool>& abandon) {
  return [&](size_t done, size_t total) {
    if (abandon) throw TaskAbandoned();
    progress = static_cast<double>(done) / static_cast<double>(total);
  };
}

}  // namespace

struct TaskRunner::ShotRenderer {
  Scene scene;
  std::unique_ptr<FrameRenderer> renderer;
  std::unique_ptr<MetropolisRenderer> metropolis;  // Metropolis pipelines only
  std::unique_ptr<GradientFrameRenderer> gradient;  // gradient-domain pipelines only
};

TaskRunner::~TaskRunner() = default;

std::shared_ptr<TaskRunner::ShotRenderer> TaskRunner::rendererFor(const Lease& lease, const ChunkFetcher& fetch) {
  const std::lock_guard lock(mutex_);
  // Most recently used first; a shot seen again moves to the front.
  const auto cached = std::find_if(renderers_.begin(), renderers_.end(),
                                   [&](const auto& entry) { return entry.first == lease.shot_id(); });
  if (cached != renderers_.end()) {
    std::rotate(renderers_.begin(), cached, cached + 1);
    return renderers_.front().second;
  }
  auto shot = std::make_shared<ShotRenderer>();
  shot->scene = loadScene(localSceneFile(lease.spec(), scenesRoot_, fetch));
  if (lease.spec().camera_zoom() > 1)
    shot->scene.camera = zoomedIn(shot->scene.camera, lease.spec().camera_zoom(), 0.5 + lease.spec().camera_shift_x(),
                                  0.5 + lease.spec().camera_shift_y());
  shot->renderer = std::make_unique<FrameRenderer>(shot->scene, settingsOf(shot->scene, lease.spec(), threads_));
  if (isMetropolisPipeline(lease.spec().pipeline()))
    shot->metropolis = std::make_unique<MetropolisRenderer>(shot->scene, metropolisSettingsOf(lease.spec(), threads_));
  if (const IntegratorTraits& integrator = integratorNamed(traitsOf(lease.spec().pipeline()).integrator);
      integrator.gradient) {
    RenderSettings settings = shot->renderer->settings();
    settings.decomposition = nullptr;
    shot->gradient = std::make_unique<GradientFrameRenderer>(shot->scene, settings,
                                                             GradientSettings{.temporal = integrator.temporal});
  }
  renderers_.insert(renderers_.begin(), {lease.shot_id(), shot});
  if (renderers_.size() > kShotsKept) renderers_.pop_back();  // tasks still using it keep their copy
  return shot;
}

TaskOutput TaskRunner::run(const Lease& lease, const ChunkFetcher& fetch, std::atomic<double>& progress,
                           const std::atomic<bool>& abandon, const ChunkFileFetcher& files) {
  switch (lease.kind()) {
    case TASK_RENDER_TILE:
      return renderTile(lease, fetch, progress, abandon);
    case TASK_ASSEMBLE_FRAME:
      return assemble(lease, fetch, files, progress);
    case TASK_GRADIENT_TILE:
      return renderGradientTile(lease, fetch, progress, abandon);
    case TASK_GRADIENT_RENDER:
      return lease.inputs_size() > 0 ? joinGradientTiles(lease, fetch, progress)
                                     : renderGradientFrame(lease, fetch, progress, abandon);
    case TASK_NOOP:
      return {};
    case TASK_MLT_SEED_POOL:
    case TASK_MLT_CHAINS:
    case TASK_MLT_MERGE:
      return runMetropolis(lease, fetch, progress, abandon);
    default:
      return filter(lease, fetch, files, progress);
  }
}

TaskOutput TaskRunner::assemble(const Lease& lease, const ChunkFetcher& fetch, const ChunkFileFetcher& files,
                                std::atomic<double>& progress) {
  if (lease.params().has_given_frame()) return handOnGivenFrame(lease, fetch);
  const std::string attempt = "attempt-" + std::to_string(lease.attempt_id());
  std::vector<std::unique_ptr<ScratchFile>> written;  // the tiles `fetch` gave, without `files`
  const ChunkFileFetcher viaScratch = [&](const ChunkRef& ref) {
    const auto& tile = written.emplace_back(std::make_unique<ScratchFile>(
        scratchPathFor(outgoingRoot_, attempt + "-input-" + std::to_string(written.size()) + ".exr")));
    writeFileAtomically(tile->path(), fetch(ref), AtomicFileWriter::Sync::No);
    return tile->path();
  };
  TaskOutput output;
  output.chunkFile = std::make_shared<const ScratchFile>(scratchPathFor(outgoingRoot_, attempt + ".exr"));
  assembleFrame(lease, files ? files : viaScratch, output.chunkFile->path(), progress);
  return output;
}

// A reference the client's cache gave: checked as any frame another party made, then
// handed on as it is.
TaskOutput TaskRunner::handOnGivenFrame(const Lease& lease, const ChunkFetcher& fetch) {
  const std::string label = "the cached reference of frame " + std::to_string(lease.params().frame());
  TaskOutput output;
  output.chunk = fetch(lease.params().given_frame());
  const FrameImage frame = decodeExr(output.chunk, label);
  if (frame.width() != lease.spec().width() || frame.height() != lease.spec().height())
    throw BadInput(label + " is " + sizeText(frame.width(), frame.height()) + ", the shot renders " +
                   sizeText(lease.spec().width(), lease.spec().height()));
  for (const char* channel : {"R", "G", "B"})
    if (!frame.hasChannel(channel)) throw BadInput(label + " has no channel \"" + channel + "\"");
  if (const std::string bad = frame.firstNonFinite(); !bad.empty())
    throw BadInput(label + " holds a non-finite value (" + bad + ")");
  return output;
}

TaskOutput TaskRunner::renderTile(const Lease& lease, const ChunkFetcher& fetch, std::atomic<double>& progress,
                                  const std::atomic<bool>& abandon) {
  const auto shot = rendererFor(lease, fetch);
  const TaskParams& params = lease.params();
  RenderSettings settings = shot->renderer->settings();
  if (params.spp() > 0) settings.spp = params.spp();
  if (params.beauty_only()) settings.decomposition = nullptr;
  settings.reflectanceSpp = params.reflectance_spp();
  if (params.motion_forward() > 0) settings.motionSpan.forward = params.motion_forward();
  if (params.motion_backward() > 0) settings.motionSpan.backward = params.motion_backward();
  // A reference measures the shot's frames: it must not share their samples, or their
  // errors would partly cancel in the comparison.
  if (params.role() == ROLE_REFERENCE) settings.firstSample = kIndependentFirstSample;
  // The n-th baseline render of a frame takes the n-th range of spp samples: together the
  // renders are the one render a longer baseline would be, cut where its samples part.
  if (params.role() == ROLE_BASELINE)
    settings.firstSample += static_cast<uint32_t>(params.baseline_repeat()) * static_cast<uint32_t>(settings.spp);
  // A chunk whose readers read no motion (features, re-rendered pixels) skips measuring it.
  const std::optional<ChunkContent> content = renderedContent(params.role());
  const bool filtering = isFilteringPipeline(lease.spec().pipeline());
  if (content && filtering) settings.motion = readsMotion(*content, stagesOf(lease.spec().pipeline()));
  const FrameRenderer renderer(*shot->renderer, settings);
  const PixelWindow& w = params.window();
  const std::vector<uint8_t> only(params.pixel_mask().begin(), params.pixel_mask().end());
  RenderStats stats;
  FrameImage tile = renderer.renderWindow(params.frame(), {w.x0(), w.y0(), w.x1(), w.y1()},
                                          abandonable(progress, abandon), &stats, only.empty() ? nullptr : &only);
  const bool intermediate = settings.decomposition && content && filtering;
  if (intermediate) keepReadChannels(*content, stagesOf(lease.spec().pipeline()), tile);
  TaskOutput output;
  output.chunk = encodeExr(tile, ExrCompression::Fast, intermediate ? halfPrecisionChannels(tile) : ChannelFilter{});
  output.metrics["samples"] = static_cast<double>(stats.samples);
  return output;
}

TaskOutput TaskRunner::renderGradientFrame(const Lease& lease, const ChunkFetcher& fetch,
                                           std::atomic<double>& progress, const std::atomic<bool>& abandon) {
  const auto shot = rendererFor(lease, fetch);
  RenderStats stats;
  const FrameImage frame = shot->gradient->render(lease.params().frame(), abandonable(progress, abandon), &stats);
  TaskOutput output;
  output.chunk = encodeExr(frame, ExrCompression::Fast);
  output.metrics["samples"] = static_cast<double>(stats.samples);
  return output;
}

TaskOutput TaskRunner::renderGradientTile(const Lease& lease, const ChunkFetcher& fetch,
                                          std::atomic<double>& progress, const std::atomic<bool>& abandon) {
  const auto shot = rendererFor(lease, fetch);
  const PixelWindow& w = lease.params().window();
  RenderStats stats;
  FrameImage estimates;
  try {
    estimates = shot->gradient->renderWindow(lease.params().frame(), {w.x0(), w.y0(), w.x1(), w.y1()},
                                             abandonable(progress, abandon), &stats);
  } catch (const std::invalid_argument& e) {
    throw BadInput(std::string("gradient tile: ") + e.what());
  }
  TaskOutput output;
  output.chunk = encodeExr(estimates, ExrCompression::Fast);
  output.metrics["samples"] = static_cast<double>(stats.samples);
  return output;
}

TaskOutput TaskRunner::joinGradientTiles(const Lease& lease, const ChunkFetcher& fetch,
                                         std::atomic<double>& progress) {
  const std::vector<TaskInput> inputs = inputsOf(lease, fetch, progress);
  std::vector<PlacedEstimates> tiles;
  for (const TaskInput& input : inputs) {
    if (input.kind != TASK_GRADIENT_TILE) throw BadInput("a gradient render joins gradient tiles only");
    const PixelWindow& w = input.params.window();
    if (input.image().width() != w.x1() - w.x0() || input.image().height() != w.y1() - w.y0())
      throw BadInput("the gradient tile at (" + std::to_string(w.x0()) + ", " + std::to_string(w.y0()) + ") is " +
                     sizeText(input.image().width(), input.image().height()) + ", its window " +
                     sizeText(w.x1() - w.x0(), w.y1() - w.y0()));
    tiles.push_back({&input.image(), w.x0(), w.y0()});
  }
  TaskOutput output;
  try {
    output.chunk = encodeExr(gradientFrameFromEstimates(tiles, lease.spec().width(), lease.spec().height()),
                             ExrCompression::Fast);
  } catch (const std::invalid_argument& e) {
    throw BadInput(std::string("gradient render of frame ") + std::to_string(lease.params().frame()) + ": " + e.what());
  }
  return output;
}

TaskOutput TaskRunner::filter(const Lease& lease, const ChunkFetcher& fetch, const ChunkFileFetcher& files,
                              std::atomic<double>& progress) {
  using Filter = TaskOutput (*)(const Lease&, std::vector<TaskInput>&);
  const std::map<TaskKind, Filter> filters = {
      {TASK_DENOISE, runDenoiseTask},     {TASK_UPSAMPLE, runUpsampleTask},   {TASK_FLOW, runFlowTask},
      {TASK_INTERPOLATE, runInterpolateTask}, {TASK_COMPOSITE, runCompositeTask}, {TASK_EVALUATE, runEvaluateTask},
      {TASK_POISSON_WINDOW, runPoissonWindowTask}, {TASK_POISSON_BLEND, runPoissonBlendTask}};
  const auto found = filters.find(lease.kind());
  if (found == filters.end())
    throw std::runtime_error("this worker cannot run tasks of kind " + std::to_string(lease.kind()));
  std::vector<TaskInput> inputs = inputsOf(lease, fetch, progress, files);
  tbb::task_arena arena(threads_ > 0 ? threads_ : tbb::task_arena::automatic);
  TaskOutput output = arena.execute([&] { return found->second(lease, inputs); });
  if (output.frame || !output.rowWindows.empty()) {
    output.chunkFile = std::make_shared<const ScratchFile>(
        scratchPathFor(outgoingRoot_, "attempt-" + std::to_string(lease.attempt_id()) + ".exr"));
    // A join's windows are read from `inputs` as they are written.
    writeOutputFrame(output, output.chunkFile->path());
  }
  progress = 1.0;
  return output;
}

std::vector<TaskInput> TaskRunner::inputsOf(const Lease& lease, const ChunkFetcher& fetch,
                                            std::atomic<double>& progress, const ChunkFileFetcher& files) {
  if (lease.input_kinds_size() != lease.inputs_size() || lease.input_params_size() != lease.inputs_size())
    throw BadInput("the lease's inputs are incomplete (kinds or parameters missing)");
  std::vector<TaskInput> inputs;
  for (int i = 0; i < lease.inputs_size(); ++i) {
    TaskInput& input = inputs.emplace_back(TaskInput{lease.input_kinds(i), lease.input_params(i), nullptr});
    const ChunkRef& ref = lease.inputs(i);
    const std::string label = "input chunk " + ref.sha256();
    if (input.kind == TASK_EVALUATE) {
      input.frame = std::make_shared<FrameImage>();
    } else if (files) {
      // Fetched now, so that a task whose inputs cannot be had fails before its work.
      const std::filesystem::path file = files(ref);
      input.decode = [this, ref, label, file] { return decodedInput(ref, [&] { return decodeExrFile(file, label); }); };
      input.decodePart = [this, ref, label, file, whole = input.decode](const InputPart& wanted) {
        return decodedPart(ref, label, file, whole, wanted);
      };
      input.halfChannels = [label, file] { return readExrHeader(file, label).halfChannels; };
    } else {
      input.decode = [this, ref, label, fetch] { return decodedInput(ref, [&] { return decodeExr(fetch(ref), label); }); };
      input.halfChannels = [ref, label, fetch] { return decodeExrHeader(fetch(ref), label).halfChannels; };
    }
    // Fetching the inputs is the first half of a filter task's work, as far as anyone can tell.
    progress = 0.5 * static_cast<double>(i + 1) / static_cast<double>(lease.inputs_size());
  }
  return inputs;
}

std::shared_ptr<FrameImage> TaskRunner::decodedInput(const ChunkRef& ref, const std::function<FrameImage()>& decode) {
  // Every kept frame was made below, mutable; a kept one is shared with the cache, so
  // TaskInput::take copies it rather than change it.
  if (auto kept = decoded_.find(ref.sha256())) return std::const_pointer_cast<FrameImage>(kept);
  auto frame = std::make_shared<FrameImage>(decode());
  requireFinite(*frame, ref);
  decoded_.keep(ref.sha256(), frame);
  return frame;
}

FrameImage TaskRunner::decodedPart(const ChunkRef& ref, const std::string& label, const std::filesystem::path& file,
                                    const std::function<std::shared_ptr<FrameImage>()>& whole,
                                    const InputPart& wanted) {
  // A frame the decoded inputs would keep is decoded whole, once, for the tasks after this
  // one too; a larger one (a 1080p keyframe) would be decoded again by each task anyway.
  if (!decoded_.find(ref.sha256())) {
    const ExrHeader header = readExrHeader(file, label);
    const size_t pixels = static_cast<size_t>(header.width) * static_cast<size_t>(header.height);
    if (!decoded_.couldKeep(DecodedInputs::frameBytes(pixels, header.channels, header.attributes))) {
      const int endRow = wanted.endRow > 0 ? wanted.endRow : header.height;
      FrameImage part = wanted.firstRow > 0 || wanted.endRow > 0
                            ? readExrRows(file, label, wanted.firstRow, endRow, wanted.keep)
                            : decodeExrFile(file, label, wanted.keep);
      requireFinite(part, ref);  // the part read: the rest is not decoded at all
      return part;
    }
  }
  return partOf(*whole(), wanted);
}

TaskOutput TaskRunner::runMetropolis(const Lease& lease, const ChunkFetcher& fetch, std::atomic<double>& progress,
                                     const std::atomic<bool>& abandon) {
  const auto shot = rendererFor(lease, fetch);
  if (!shot->metropolis)
    throw BadInput("a Metropolis task in a shot of pipeline " + pipelineLabel(lease.spec().pipeline()));
  const MetropolisRenderer& renderer = *shot->metropolis;
  TaskOutput output;
  if (lease.kind() == TASK_MLT_SEED_POOL) {
    output = runSeedPoolTask(renderer, lease);
  } else {
    std::atomic<double> fetching{0};
    const std::vector<TaskInput> inputs = inputsOf(lease, fetch, fetching);
    output = lease.kind() == TASK_MLT_CHAINS ? runChainsTask(renderer, lease, inputs,
                                                             [&](double done) {
                                                               if (abandon) throw TaskAbandoned();
                                                               progress = done;
                                                             })
                                             : runMergeTask(renderer, lease, inputs);
  }
  progress = 1.0;
  return output;
}

}  // namespace pathfarm::farm
