#include "worker/metropolis_tasks.h"

#include "contract/pipeline.h"
#include "image/exr_io.h"
#include "worker/failure_class.h"
#include "worker/filter_inputs.h"

namespace pathfarm::farm {
namespace {

constexpr const char* kSeedPoolAttribute = "pathfarm.mlt.seed_pool";
constexpr const char* kColor[3] = {"R", "G", "B"};

FrameWindow windowOf(const Lease& lease) {
  return {lease.params().window_first(), lease.params().window_frames()};
}

std::string blockAttribute(int block) { return "pathfarm.mlt.block." + std::to_string(block); }
std::string blockChannel(int frameIndex, int block, int c) {
  return std::to_string(frameIndex) + "." + std::to_string(block) + "." + kColor[c];
}

SeedPool poolOf(const std::vector<TaskInput>& inputs, FrameWindow window) {
  const TaskInput& input = findInput(
      inputs, [&](const TaskInput& i) { return i.kind == TASK_MLT_SEED_POOL && i.params.window_first() == window.first; },
      "the seed pool of the window starting at frame " + std::to_string(window.first));
  const auto text = input.image().attributes().find(kSeedPoolAttribute);
  if (text == input.image().attributes().end()) throw BadInput("the seed-pool chunk carries no seed pool");
  return SeedPool::parse(text->second);
}

// The blocks of one chain task's chunk, as the renderer returned them.
void readBlocks(const TaskInput& input, FrameWindow window, std::vector<BlockResult>& blocks) {
  const int first = input.params.block_first();
  for (int block = first; block < first + input.params.block_count(); ++block) {
    BlockResult result;
    result.block = block;
    const auto stats = input.image().attributes().find(blockAttribute(block));
    if (stats == input.image().attributes().end())
      throw BadInput("chain chunk lacks the statistics of block " + std::to_string(block));
    result.stats = MutationStats::parse(stats->second);
    for (int f = 0; f < window.count; ++f) {
      FrameImage frame(input.image().width(), input.image().height());
      for (int c = 0; c < 3; ++c) frame.addChannel(kColor[c]) = input.image().channel(blockChannel(f, block, c));
      result.frames.push_back(std::move(frame));
    }
    blocks.push_back(std::move(result));
  }
}

}  // namespace

MetropolisSettings metropolisSettingsOf(const ShotSpec& spec, int threads) {
  MetropolisSettings settings;
  settings.method = parseMetropolisMethod(std::string(traitsOf(spec.pipeline()).integrator));
  settings.width = spec.width();
  settings.height = spec.height();
  settings.maxDepth = spec.max_depth();
  settings.mutationsPerPixel = spec.mutations_per_pixel();
  if (spec.bootstrap_samples() > 0) settings.bootstrapSamples = static_cast<uint64_t>(spec.bootstrap_samples());
  settings.chains = spec.mlt_chains();
  settings.chainsPerBlock = spec.chains_per_block();
  settings.temporalDelta = spec.temporal_delta() > 0 ? spec.temporal_delta() : settings.temporalDelta;
  settings.tuneDelta = spec.tune_delta();
  settings.threads = threads;
  return settings;
}

TaskOutput runSeedPoolTask(const MetropolisRenderer& renderer, const Lease& lease) {
  const SeedPool pool = renderer.seedPool(windowOf(lease));
  FrameImage chunk(1, 1);
  chunk.addChannel("R");
  chunk.attributes()[kSeedPoolAttribute] = pool.serialize();
  TaskOutput output;
  output.chunk = encodeExr(chunk, ExrCompression::Fast);
  output.metrics["normalization"] = pool.normalization;
  output.metrics["samples"] = static_cast<double>(pool.bootstrapSamples);
  return output;
}

TaskOutput runChainsTask(const MetropolisRenderer& renderer, const Lease& lease, const std::vector<TaskInput>& inputs,
                         const std::function<void(double)>& progress) {
  const FrameWindow window = windowOf(lease);
  const SeedPool pool = poolOf(inputs, window);
  const int first = lease.params().block_first(), count = lease.params().block_count();
  if (count < 1) throw BadInput("a chain task without blocks");
  FrameImage chunk(lease.spec().width(), lease.spec().height());
  MutationStats total;
  for (int block = first; block < first + count; ++block) {
    const BlockResult result = renderer.runBlock(window, pool, block, [&](size_t done, size_t chains) {
      progress((static_cast<double>(block - first) + static_cast<double>(done) / static_cast<double>(chains)) / count);
    });
    for (int f = 0; f < window.count; ++f)
      for (int c = 0; c < 3; ++c)
        chunk.addChannel(blockChannel(f, block, c)) = result.frames[static_cast<size_t>(f)].channel(kColor[c]);
    chunk.attributes()[blockAttribute(block)] = result.stats.serialize();
    total.add(result.stats);
  }
  TaskOutput output;
  output.chunk = encodeExr(chunk, ExrCompression::Fast);
  output.metrics["samples"] = static_cast<double>(total.mutations());
  if (total.temporalKind >= 0) {
    const auto k = static_cast<size_t>(total.temporalKind);
    output.metrics["temporal_proposed"] = static_cast<double>(total.proposed[k]);
    output.metrics["temporal_accepted"] = static_cast<double>(total.accepted[k]);
  }
  return output;
}

TaskOutput runMergeTask(const MetropolisRenderer& renderer, const Lease& lease, const std::vector<TaskInput>& inputs) {
  const FrameWindow window = windowOf(lease);
  const SeedPool pool = poolOf(inputs, window);
  std::vector<BlockResult> blocks;
  for (const TaskInput& input : inputs)
    if (input.kind == TASK_MLT_CHAINS) readBlocks(input, window, blocks);
  std::vector<FrameImage> frames = renderer.merge(window, pool, std::move(blocks));
  TaskOutput output;
  output.chunk = encodeExr(frames.at(static_cast<size_t>(lease.params().frame() - window.first)));
  return output;
}

}  // namespace pathfarm::farm
