#include "scheduler/planner.h"
#include "scheduler/quoted_text.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <set>
#include <string>

#include "postproc/poisson/window_blend.h"
#include "renderer/integrators/frame_integrator.h"
#include "renderer/decomposition/decomposition.h"

namespace pathfarm::farm {
namespace {

PipelineFamily familyOf(Pipeline pipeline) {
  try {
    return traitsOf(pipeline).family;
  } catch (const std::invalid_argument&) {
    throw PlanError(pipeline == PIPELINE_UNSPECIFIED
                        ? "the shot names no pipeline (a client older than this scheduler sends it by name: upgrade "
                          "the client; this farm runs: " + pipelineNames() + ")"
                        : pipelineLabel(pipeline) + " is not available (this farm runs: " + pipelineNames() + ")");
  }
}

void checkRenderSpec(const ShotSpec& spec) {
  if (spec.frame_end() < spec.frame_start() || spec.frame_start() < 0)
    throw PlanError("frames: the range must satisfy 0 <= start <= end");
  if (spec.width() < 1 || spec.height() < 1 || spec.width() > 16384 || spec.height() > 16384)
    throw PlanError("resolution: width and height must be 1 to 16384");
  if (spec.spp() < 1) throw PlanError("spp: must be at least 1");
  if (spec.tile() < 8) throw PlanError("tile: must be at least 8 pixels");
  if (spec.reference_spp() < 0)
    throw PlanError("reference_spp: must not be negative (the client chooses \"auto\" before it submits)");
  if (spec.baseline_repeats() < 0 || spec.baseline_repeats() > kMaxBaselineRepeats)
    throw PlanError("baseline_repeats: must be 1 to " + std::to_string(kMaxBaselineRepeats));
  const auto baselineSamples = static_cast<uint64_t>(baselineRepeatsOf(spec)) * static_cast<uint64_t>(spec.spp());
  if (baselineRepeatsOf(spec) > 1 && spec.first_sample() + baselineSamples > kIndependentFirstSample)
    throw PlanError("baseline_repeats: " + std::to_string(baselineRepeatsOf(spec)) + " renders of " +
                    std::to_string(spec.spp()) + " spp would reach the reference's samples");
  if (!(spec.camera_zoom() >= 0 && spec.camera_zoom() <= 1024))
    throw PlanError("camera_zoom: must be 0 to 1024 (up to 1: no zoom)");
  if (!(std::abs(spec.camera_shift_x()) <= 0.5 && std::abs(spec.camera_shift_y()) <= 0.5))
    throw PlanError("camera_shift_x, camera_shift_y: the window's centre must lie in the picture (-0.5 to 0.5)");
  for (const int64_t frame : spec.evaluation_frames())
    if (frame < spec.frame_start() || frame > spec.frame_end())
      throw PlanError("evaluation_frames: frame " + std::to_string(frame) + " is not in the shot");
  std::set<int64_t> known;
  for (const KnownReference& reference : spec.known_references()) {
    const auto& frames = spec.evaluation_frames();
    if (std::find(frames.begin(), frames.end(), reference.frame()) == frames.end())
      throw PlanError("known_references: frame " + std::to_string(reference.frame()) + " is not an evaluation frame");
    if (!known.insert(reference.frame()).second)
      throw PlanError("known_references: frame " + std::to_string(reference.frame()) + " is given twice");
  }
}

void setWindow(TaskParams& params, int x0, int y0, int x1, int y1) {
  PixelWindow* window = params.mutable_window();
  window->set_x0(x0);
  window->set_y0(y0);
  window->set_x1(x1);
  window->set_y1(y1);
}

// Appends the tiles of one frame's render and the task assembling them; returns the
// assemble task's index. `adjust` may add to every tile's parameters. A frame of more
// than kMaxAssemblyInputs tiles is assembled in two steps: blocks of tiles into regions
// (assemble tasks with a window), the regions into the frame; so no lease names more
// inputs than a gRPC message holds.
size_t planFrameRender(const ShotSpec& spec, int64_t frame, TaskRole role, int spp, bool beautyOnly,
                       std::vector<PlannedTask>& plan, const std::function<void(TaskParams&)>& adjust = {}) {
  const int tile = spec.tile();
  const int64_t across = (spec.width() + tile - 1) / tile, down = (spec.height() + tile - 1) / tile;
  // Tiles per region: whole rows of tiles when a row fits, else part of a row.
  const int64_t regionAcross = std::min(across, kMaxAssemblyInputs);
  const int64_t regionDown = across * down <= kMaxAssemblyInputs ? down : std::max<int64_t>(1, kMaxAssemblyInputs / regionAcross);
  const bool inRegions = across * down > kMaxAssemblyInputs;
  PlannedTask assemble{TASK_ASSEMBLE_FRAME, {}, {}, role == ROLE_OUTPUT};
  assemble.params.set_frame(frame);
  assemble.params.set_role(role);
  for (int64_t ry = 0; ry < down; ry += regionDown) {
    for (int64_t rx = 0; rx < across; rx += regionAcross) {
      PlannedTask region{TASK_ASSEMBLE_FRAME, assemble.params, {}};
      const auto x0 = static_cast<int>(rx * tile), y0 = static_cast<int>(ry * tile);
      setWindow(region.params, x0, y0, std::min(spec.width(), static_cast<int>((rx + regionAcross) * tile)),
                std::min(spec.height(), static_cast<int>((ry + regionDown) * tile)));
      for (int y = y0; y < region.params.window().y1(); y += tile) {
        for (int x = x0; x < region.params.window().x1(); x += tile) {
          PlannedTask render{TASK_RENDER_TILE, {}, {}};
          render.params.set_frame(frame);
          render.params.set_role(role);
          render.params.set_spp(spp);
          render.params.set_beauty_only(beautyOnly);
          if (adjust) adjust(render.params);
          setWindow(render.params, x, y, std::min(x + tile, spec.width()), std::min(y + tile, spec.height()));
          (inRegions ? region : assemble).dependencies.push_back(plan.size());
          plan.push_back(std::move(render));
        }
      }
      if (!inRegions) continue;
      assemble.dependencies.push_back(plan.size());
      plan.push_back(std::move(region));
    }
  }
  plan.push_back(std::move(assemble));
  return plan.size() - 1;
}

// The task whose output is the frame's reference: the frame the client gave, handed on, or
// the frame rendered at reference_spp.
size_t planReference(const ShotSpec& spec, int64_t frame, std::vector<PlannedTask>& plan) {
  for (const KnownReference& known : spec.known_references()) {
    if (known.frame() != frame) continue;
    PlannedTask given{TASK_ASSEMBLE_FRAME, {}, {}};
    given.params.set_frame(frame);
    given.params.set_role(ROLE_REFERENCE);
    *given.params.mutable_given_frame() = known.chunk();
    plan.push_back(std::move(given));
    return plan.size() - 1;
  }
  return planFrameRender(spec, frame, ROLE_REFERENCE, spec.reference_spp(), true, plan);
}

// Per evaluation frame, the tasks whose outputs the evaluation compares (every stage the
// frame passes through).
using StageOutputs = std::map<int64_t, std::vector<size_t>>;

// `filtering`: the shot is not itself the baseline, so its pt cost and error are measured on
// baseline renders of the evaluation frames (unless the cost is given and no error is asked).
void planEvaluation(const ShotSpec& spec, bool filtering, const StageOutputs& stages, std::vector<PlannedTask>& plan) {
  const bool measureBaseline = filtering && (spec.baseline_core_seconds() <= 0 || spec.reference_spp() > 0);
  PlannedTask evaluate{TASK_EVALUATE, {}, {}};
  for (const int64_t frame : spec.evaluation_frames()) {
    // Several renders narrow pt's error; without a reference only its cost is measured.
    const int repeats = spec.reference_spp() > 0 ? baselineRepeatsOf(spec) : 1;
    for (int repeat = 0; measureBaseline && repeat < repeats; ++repeat) {
      const size_t first = plan.size();
      evaluate.dependencies.push_back(planFrameRender(spec, frame, ROLE_BASELINE, spec.spp(), true, plan));
      for (size_t task = first; task < plan.size(); ++task) plan[task].params.set_baseline_repeat(repeat);
    }
    if (spec.reference_spp() == 0) continue;
    evaluate.dependencies.push_back(planReference(spec, frame, plan));
    const std::vector<size_t>& outputs = stages.at(frame);
    evaluate.dependencies.insert(evaluate.dependencies.end(), outputs.begin(), outputs.end());
  }
  if (spec.reference_spp() > 0 && !spec.evaluation_frames().empty()) plan.push_back(std::move(evaluate));
}

// Indices 0 .. count - 1 with every `every`-th first (0, every, 2 every, ...), then the
// rest in order: tasks are leased in the order they are planned, so these frames finish
// first (ShotSpec::preview_every).
std::vector<size_t> previewOrder(size_t count, int every) {
  std::vector<size_t> order;
  order.reserve(count);
  const size_t stride = static_cast<size_t>(std::max(every, 1));
  for (size_t i = 0; i < count; i += stride) order.push_back(i);
  if (stride > 1)
    for (size_t i = 0; i < count; ++i)
      if (i % stride != 0) order.push_back(i);
  return order;
}

void planPathTracing(const ShotSpec& spec, std::vector<PlannedTask>& plan) {
  StageOutputs stages;
  const auto frames = static_cast<size_t>(spec.frame_end() - spec.frame_start() + 1);
  for (const size_t i : previewOrder(frames, spec.preview_every())) {
    const int64_t frame = spec.frame_start() + static_cast<int64_t>(i);
    stages[frame].push_back(planFrameRender(spec, frame, ROLE_OUTPUT, spec.spp(), false, plan));
  }
  planEvaluation(spec, false, stages, plan);
}

// The components whose irradiance moves by optical flow: those whose first non-specular
// vertex is the primary hit (their expression starts with ED) and the residual. Specular
// components move along their own (manifold) motion.
std::vector<std::string> flowComponents(const ShotSpec& spec) {
  const Decomposition decomposition = Decomposition::parse(spec.decompose());
  std::vector<std::string> names;
  for (const Component& component : decomposition.components())
    if (component.expression.rfind("ED", 0) == 0) names.push_back(component.name);
  names.push_back(decomposition.name(decomposition.residual()));
  return names;
}

PlannedTask task(TaskKind kind, int64_t frame, std::vector<size_t> dependencies) {
  PlannedTask planned{kind, {}, std::move(dependencies)};
  planned.params.set_frame(frame);
  return planned;
}

size_t push(PlannedTask planned, std::vector<PlannedTask>& plan) {
  plan.push_back(std::move(planned));
  return plan.size() - 1;
}

// A filter task of a frame taller than a filter window, as a task per window of rows (each
// holding only its rows, with the task's inputs) and the task itself, which joins them.
PlannedTask inWindows(PlannedTask whole, const ShotSpec& spec, std::vector<PlannedTask>& plan) {
  const std::vector<RowWindow> windows = filterWindowsOf(spec);
  if (windows.size() < 2) return whole;
  std::vector<size_t> joined;
  for (const RowWindow& rows : windows) {
    PlannedTask window = whole;
    window.output = false;
    setWindow(window.params, 0, rows.first, spec.width(), rows.end);
    joined.push_back(push(std::move(window), plan));
  }
  whole.dependencies = std::move(joined);
  return whole;
}

void planFiltering(const ShotSpec& spec, std::vector<PlannedTask>& plan) {
  checkRenderSpec(spec);
  const FilteringStages stages = stagesOf(spec.pipeline());
  if (spec.decompose().empty() || spec.decompose() == "none")
    throw PlanError("pipeline \"" + std::string(pipelineName(spec.pipeline())) + "\" filters path-space components: decompose must not be none");
  if (stages.upsample && (spec.width() % 2 != 0 || spec.height() % 2 != 0))
    throw PlanError("resolution: upsampling pipelines need an even width and height");
  if (spec.keyframe_interval() < 1) throw PlanError("keyframe_interval: must be at least 1");
  if (spec.rerender_spp() < 0) throw PlanError("rerender_spp: must be at least 1 (or 0 for the default)");
  if (spec.filter_window_rows() != 0 && spec.filter_window_rows() < kMinFilterWindowRows)
    throw PlanError("filter_window_rows: must be at least " + std::to_string(kMinFilterWindowRows));
  std::vector<std::string> components;
  try {
    components = flowComponents(spec);
  } catch (const std::invalid_argument& e) {
    throw PlanError(std::string("decompose: ") + e.what());
  }

  const std::vector<int64_t> keyframes = keyframesOf(spec);
  const int keyframeSpp = keyframeSppOf(spec);
  std::map<int64_t, size_t> rendered;  // frame -> its assembled render (keyframe or features)
  const std::vector<size_t> keyframeOrder = previewOrder(keyframes.size(), spec.preview_every());
  for (const size_t i : keyframeOrder) {
    // Its motion vectors reach the neighbouring keyframes directly (one frame at the ends).
    const int forward = i + 1 < keyframes.size() ? static_cast<int>(keyframes[i + 1] - keyframes[i]) : 1;
    const int backward = i > 0 ? static_cast<int>(keyframes[i] - keyframes[i - 1]) : 1;
    rendered[keyframes[i]] = planFrameRender(spec, keyframes[i], ROLE_KEYFRAME, keyframeSpp, false, plan,
                                             [&](TaskParams& params) {
                                               params.set_motion_forward(forward);
                                               params.set_motion_backward(backward);
                                             });
  }

  // In-between frames: a few samples of their own features (feature_check.h), and their
  // reflectance at about the keyframes' spp, which modulates their interpolation at texture
  // edges.
  const int featureSpp = std::clamp(spec.feature_spp(), 1, spec.spp());
  for (size_t i = 1; i < keyframes.size(); ++i)
    for (int64_t frame = keyframes[i - 1] + 1; frame < keyframes[i]; ++frame)
      rendered[frame] = planFrameRender(spec, frame, ROLE_FEATURES, featureSpp, false, plan, [&](TaskParams& params) {
        params.set_reflectance_spp(std::max(featureSpp, ownReflectanceSpp(keyframeSpp)));
      });

  StageOutputs evaluated;
  std::map<int64_t, size_t> finalOf;  // frame -> the task whose frame the composite finishes
  // d re-renders nothing, so a composite would only copy: its denoise writes the final frame.
  const bool denoiseIsFinal = !stages.upsample && !stages.interpolate;
  for (const size_t i : keyframeOrder) {
    const int64_t frame = keyframes[i];
    PlannedTask denoise = task(TASK_DENOISE, frame, {rendered.at(frame)});
    if (i > 0) denoise.dependencies.push_back(rendered.at(keyframes[i - 1]));
    if (i + 1 < keyframes.size()) denoise.dependencies.push_back(rendered.at(keyframes[i + 1]));
    if (denoiseIsFinal) {
      denoise.params.set_role(ROLE_OUTPUT);
      denoise.output = true;
      evaluated[frame] = {rendered.at(frame), push(inWindows(std::move(denoise), spec, plan), plan)};
      continue;
    }
    finalOf[frame] = push(inWindows(std::move(denoise), spec, plan), plan);
    if (stages.upsample)
      finalOf[frame] = push(inWindows(task(TASK_UPSAMPLE, frame, {finalOf[frame], rendered.at(frame)}), spec, plan), plan);
    evaluated[frame] = {rendered.at(frame), finalOf[frame]};
  }

  for (size_t i = 1; i < keyframes.size(); ++i) {
    const int64_t k0 = keyframes[i - 1], k1 = keyframes[i];
    if (k1 - k0 < 2) continue;
    const auto between = [&](TaskKind kind, int64_t frame, std::vector<size_t> dependencies) {
      PlannedTask planned = task(kind, frame, std::move(dependencies));
      planned.params.set_keyframe_before(k0);
      planned.params.set_keyframe_after(k1);
      return planned;
    };
    std::vector<size_t> interpolationInputs = {finalOf.at(k0), finalOf.at(k1)};
    for (const std::string& component : components) {
      PlannedTask flow = between(TASK_FLOW, k0, {finalOf.at(k0), finalOf.at(k1)});
      flow.params.set_component(component);
      interpolationInputs.push_back(push(inWindows(std::move(flow), spec, plan), plan));
    }
    for (int64_t frame = k0 + 1; frame < k1; ++frame) {
      std::vector<size_t> inputs = interpolationInputs;
      inputs.push_back(rendered.at(frame));
      finalOf[frame] = push(inWindows(between(TASK_INTERPOLATE, frame, inputs), spec, plan), plan);
      evaluated[frame] = {finalOf[frame]};
    }
  }

  for (const auto& [frame, stage] : finalOf) {
    PlannedTask composite = task(TASK_COMPOSITE, frame, {stage});
    composite.output = true;
    evaluated[frame].push_back(push(inWindows(std::move(composite), spec, plan), plan));
  }
  planEvaluation(spec, true, evaluated, plan);
}

// The edge of a gradient frame's tiles: the shot's tile, doubled until a frame has at most
// kMaxAssemblyInputs tiles (its gradient_render's inputs).
int gradientTileEdge(const ShotSpec& spec) {
  int64_t edge = std::max(spec.tile(), 1);
  const auto tiles = [&] { return ((spec.width() + edge - 1) / edge) * ((spec.height() + edge - 1) / edge); };
  while (tiles() > kMaxAssemblyInputs) edge *= 2;
  return static_cast<int>(edge);
}

// A frame's gradient render: its tiles sampled apart (each a task a lost worker costs
// little of) and joined into the frame's layers; one task when a tile is the frame.
size_t planGradientFrame(const ShotSpec& spec, int64_t frame, std::vector<PlannedTask>& plan) {
  PlannedTask layers = task(TASK_GRADIENT_RENDER, frame, {});
  const int edge = gradientTileEdge(spec);
  if (edge < spec.width() || edge < spec.height()) {
    for (int y = 0; y < spec.height(); y += edge) {
      for (int x = 0; x < spec.width(); x += edge) {
        PlannedTask tile = task(TASK_GRADIENT_TILE, frame, {});
        setWindow(tile.params, x, y, std::min(x + edge, spec.width()), std::min(y + edge, spec.height()));
        layers.dependencies.push_back(push(std::move(tile), plan));
      }
    }
  }
  return push(std::move(layers), plan);
}

// Temporal gradient-domain path tracing (Manzi et al. 2016): a gradient render per frame
// (planGradientFrame; the temporal offset of frame f reaches f + 1), a Poisson
// reconstruction per window of frames, and a blend per frame over the windows covering it.
void planGradientDomain(const ShotSpec& spec, std::vector<PlannedTask>& plan) {
  checkRenderSpec(spec);
  if (spec.poisson_window() < 1 || spec.poisson_overlap() < 0 || spec.poisson_overlap() >= spec.poisson_window())
    throw PlanError("poisson_window, poisson_overlap: need 0 <= overlap < window");
  if (spec.poisson_norm() != "l1" && spec.poisson_norm() != "l2") throw PlanError("poisson_norm: \"l1\" or \"l2\"");
  std::map<int64_t, size_t> rendered;
  for (int64_t frame = spec.frame_start(); frame <= spec.frame_end(); ++frame)
    rendered[frame] = planGradientFrame(spec, frame, plan);
  std::map<int64_t, std::vector<size_t>> covering;  // frame -> its windows, in order
  const auto frames = static_cast<size_t>(spec.frame_end() - spec.frame_start() + 1);
  for (const PoissonWindow& window :
       planWindows(frames, static_cast<size_t>(spec.poisson_window()), static_cast<size_t>(spec.poisson_overlap()))) {
    const int64_t first = spec.frame_start() + static_cast<int64_t>(window.first);
    PlannedTask solve = task(TASK_POISSON_WINDOW, first, {});
    solve.params.set_window_first(first);
    solve.params.set_window_frames(static_cast<int32_t>(window.count));
    for (int64_t frame = first; frame < first + static_cast<int64_t>(window.count); ++frame)
      solve.dependencies.push_back(rendered.at(frame));
    const size_t index = push(std::move(solve), plan);
    for (int64_t frame = first; frame < first + static_cast<int64_t>(window.count); ++frame)
      covering[frame].push_back(index);
  }
  StageOutputs evaluated;
  for (const auto& [frame, windows] : covering) {
    PlannedTask blend = task(TASK_POISSON_BLEND, frame, windows);
    blend.dependencies.push_back(rendered.at(frame));  // its directly seen emission
    blend.output = true;
    evaluated[frame] = {push(std::move(blend), plan)};
  }
  planEvaluation(spec, true, evaluated, plan);
}

// The chain blocks [first, first + count) of each of `tasks` chain-batch tasks: `blocks`
// split as evenly as possible, in order.
std::vector<std::pair<int, int>> splitBlocks(int blocks, int tasks) {
  std::vector<std::pair<int, int>> ranges;
  for (int t = 0, first = 0; t < tasks; ++t) {
    const int count = blocks / tasks + (t < blocks % tasks ? 1 : 0);
    ranges.emplace_back(first, count);
    first += count;
  }
  return ranges;
}

// Metropolis light transport (docs/metropolis.md): per window of frames (one frame for
// mlt) a seed pool, chain-batch tasks over ranges of chain blocks, and a merge per frame.
void planMetropolis(const ShotSpec& spec, std::vector<PlannedTask>& plan) {
  checkRenderSpec(spec);
  if (spec.mlt_window() < 1) throw PlanError("mlt_window: must be at least 1");
  if (!(spec.mutations_per_pixel() > 0)) throw PlanError("mutations_per_pixel: must be positive");
  if (spec.mlt_chains() < 1 || spec.chains_per_block() < 1 || spec.chain_tasks() < 1)
    throw PlanError("mlt_chains, chains_per_block, chain_tasks: must be at least 1");
  if (spec.bootstrap_samples() < 0) throw PlanError("bootstrap_samples: must be at least 1, or 0 for a count sized to the window");
  if (spec.pipeline() == PIPELINE_TMLT && !(spec.temporal_delta() > 0)) throw PlanError("temporal_delta: must be positive");
  const int blocks = (spec.mlt_chains() + spec.chains_per_block() - 1) / spec.chains_per_block();
  const int64_t length = spec.pipeline() == PIPELINE_MLT ? 1 : spec.mlt_window();
  StageOutputs evaluated;
  for (int64_t first = spec.frame_start(); first <= spec.frame_end(); first += length) {
    const int64_t count = std::min(length, spec.frame_end() - first + 1);
    const auto windowTask = [&](TaskKind kind, int64_t frame, std::vector<size_t> dependencies) {
      PlannedTask planned = task(kind, frame, std::move(dependencies));
      planned.params.set_window_first(first);
      planned.params.set_window_frames(static_cast<int32_t>(count));
      return planned;
    };
    const size_t pool = push(windowTask(TASK_MLT_SEED_POOL, first, {}), plan);
    std::vector<size_t> merged = {pool};
    for (const auto& [firstBlock, blockCount] : splitBlocks(blocks, std::min(blocks, spec.chain_tasks()))) {
      PlannedTask chains = windowTask(TASK_MLT_CHAINS, first, {pool});
      chains.params.set_block_first(firstBlock);
      chains.params.set_block_count(blockCount);
      merged.push_back(push(std::move(chains), plan));
    }
    for (int64_t frame = first; frame < first + count; ++frame) {
      PlannedTask merge = windowTask(TASK_MLT_MERGE, frame, merged);
      merge.output = true;
      evaluated[frame] = {push(std::move(merge), plan)};
    }
  }
  planEvaluation(spec, true, evaluated, plan);
}

}  // namespace

std::vector<PlannedTask> planShot(const ShotSpec& spec) {
  std::vector<PlannedTask> plan;
  switch (familyOf(spec.pipeline())) {
    case PipelineFamily::Plain:
      checkRenderSpec(spec);
      planPathTracing(spec, plan);
      break;
    case PipelineFamily::Filtering:
      planFiltering(spec, plan);
      break;
    case PipelineFamily::Gradient:
      planGradientDomain(spec, plan);
      break;
    case PipelineFamily::Metropolis:
      planMetropolis(spec, plan);
      break;
    case PipelineFamily::Noop:
      if (spec.noop_tasks() < 1) throw PlanError("noop_tasks: must be at least 1");
      plan.assign(static_cast<size_t>(spec.noop_tasks()), PlannedTask{TASK_NOOP, {}, {}});
      break;
    case PipelineFamily::Choice:
      throw PlanError("pipeline \"auto\" is chosen by a probe before the shot is submitted (pathfarm submit and "
                      "pathfarm local do it); submit the pipeline it chose");
  }
  return plan;
}

bool isValidTag(const std::string& tag) {
  return !tag.empty() && tag.size() <= 64 && std::all_of(tag.begin(), tag.end(), [](unsigned char c) {
    return std::isalnum(c) || c == '-' || c == '_' || c == '.';
  });
}

int64_t plannedTasksAtLeast(const ShotSpec& spec) {
  if (spec.pipeline() == PIPELINE_NOOP) return std::max<int64_t>(spec.noop_tasks(), 0);
  const double frames = std::max<double>(static_cast<double>(spec.frame_end()) - static_cast<double>(spec.frame_start()) + 1, 0);
  double perFrame = 1;  // every pipeline's output task
  if ((spec.pipeline() == PIPELINE_PT || isFilteringPipeline(spec.pipeline())) && spec.tile() > 0) {
    const auto tilesAlong = [&](int pixels) { return std::ceil(std::max(pixels, 0) / static_cast<double>(spec.tile())); };
    perFrame = tilesAlong(spec.width()) * tilesAlong(spec.height()) + 1;
  }
  const double tasks = frames * perFrame;
  return tasks >= 9e18 ? std::numeric_limits<int64_t>::max() : static_cast<int64_t>(tasks);
}

std::vector<PlannedTask> planShotWithin(const ShotSpec& spec, const ShotLimits& limits) {
  for (const std::string& tag : spec.required_tags())
    if (!isValidTag(tag)) throw PlanError("required_tags: " + quotedInput(tag) + " is not a tag (letters, digits, '-', '_', '.')");
  const int64_t frames = spec.frame_end() - spec.frame_start() + 1;
  if (frames > limits.maxFrames)
    throw PlanError("frames: " + std::to_string(frames) + " frames is more than this scheduler takes in one shot (" +
                    std::to_string(limits.maxFrames) + "); split the shot");
  const double pixelFrames = static_cast<double>(spec.width()) * spec.height() * static_cast<double>(frames);
  if (pixelFrames > limits.maxPixelFrames)
    throw PlanError("resolution x frames: " + std::to_string(static_cast<int64_t>(pixelFrames)) +
                    " pixel-frames is more than this scheduler takes in one shot (" +
                    std::to_string(static_cast<int64_t>(limits.maxPixelFrames)) + "); split the shot");
  // Within those a shot of 8-pixel tiles can still plan 1.6e10 tasks: counted first, it is
  // refused before it takes minutes and gigabytes to plan.
  if (const int64_t tasks = plannedTasksAtLeast(spec); tasks > limits.maxTasks)
    throw PlanError("the shot plans at least " + std::to_string(tasks) + " tasks, more than this scheduler takes (" +
                    std::to_string(limits.maxTasks) + ", --max-tasks-per-shot); use larger tiles or split the shot");
  std::vector<PlannedTask> plan = planShot(spec);
  if (static_cast<int64_t>(plan.size()) > limits.maxTasks)
    throw PlanError("the shot plans " + std::to_string(plan.size()) + " tasks, more than this scheduler takes (" +
                    std::to_string(limits.maxTasks) + ", --max-tasks-per-shot); use larger tiles or split the shot");
  return plan;
}

}  // namespace pathfarm::farm
