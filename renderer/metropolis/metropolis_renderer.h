#pragma once
// Metropolis light transport over windows of frames: the API the farm and the CLI use.
//
// A window's render is three steps, each a farm task if one likes:
//   1. seedPool(window): the bootstrap; gives the normalization b and every chain's seed
//      (SeedPool::serialize() ships it as text).
//   2. runBlock(window, pool, block) for every block 0 .. blocks() - 1, anywhere, in any
//      grouping: a block is `chainsPerBlock` chains and its result depends only on the
//      scene, the settings, the pool and the block index.
//   3. merge(window, pool, results): every block's own result, each exactly once (do not
//      pre-sum blocks); the merged frames are the same bits however blocks were grouped
//      into tasks and whatever the thread counts.
// render(window) does all three in one process with the same bits.
//
// Methods: Pssmlt (Kelemen et al. 2002, with time as one primary coordinate across the
// window), and PathSpace ("mlt", Veach and Guibas) and Temporal ("tmlt", Van de Woestijne
// et al. 2017), whose path-space chain state lives in renderer/metropolis/path_space/.
// Each frame's image estimates radiance (R, G, B) and carries the chains' statistics in
// "pathfarm.mlt.*" attributes (mutation_stats.h).
#include <memory>
#include <string>
#include <vector>

#include "image/frame_image.h"
#include "renderer/metropolis/block_result.h"
#include "renderer/metropolis/chain_driver.h"
#include "renderer/metropolis/seed_pool.h"
#include "renderer/scene/scene.h"

namespace pathfarm {

enum class MetropolisMethod { Pssmlt, PathSpace /* "mlt": frame by frame */, Temporal /* "tmlt" */ };

// "pssmlt", "mlt", "tmlt"; parse throws std::invalid_argument for another name.
std::string nameOf(MetropolisMethod method);
MetropolisMethod parseMetropolisMethod(const std::string& name);

struct MetropolisSettings {
  MetropolisMethod method = MetropolisMethod::Pssmlt;
  int width = 64, height = 64, maxDepth = 8;
  double mutationsPerPixel = 64;  // per frame
  std::optional<uint64_t> bootstrapSamples;  // none: sized to the window (ChainSettings)
  int chains = 64;
  int chainsPerBlock = 16;
  double largeStepProbability = 0.3;
  // Of the other steps, the share that moves only the path's time (the temporal mutation).
  double temporalStepProbability = 0.2;
  double temporalDelta = 1;  // D, frames
  bool tuneDelta = false;
  double targetTemporalAcceptance = 0.23;
  int threads = 0;  // 0: every core

  // The scene's resolution and maximum depth, the rest as above.
  static MetropolisSettings defaultsOf(const Scene& scene);
  // Throws std::invalid_argument naming the first setting out of range.
  void validate() const;
  int blocks() const { return (chains + chainsPerBlock - 1) / chainsPerBlock; }
  ChainSettings chainSettings(uint64_t sceneSeed) const;
};

class MetropolisRenderer {
 public:
  // Builds the shot's geometry once. Throws std::invalid_argument for bad settings.
  MetropolisRenderer(const Scene& scene, MetropolisSettings settings);
  ~MetropolisRenderer();

  const MetropolisSettings& settings() const { return settings_; }
  int blocks() const { return settings_.blocks(); }

  // Every call below throws std::invalid_argument for an empty window, a camera shutter
  // of zero length, or a window of more than one frame for PathSpace ("mlt"). A scene
  // whose light never reaches the camera gives an empty pool, black frames and a warning.
  SeedPool seedPool(FrameWindow window) const;
  BlockResult runBlock(FrameWindow window, const SeedPool& pool, int block, const ChainProgress& progress = {}) const;
  std::vector<FrameImage> merge(FrameWindow window, const SeedPool& pool, std::vector<BlockResult> results) const;
  // Progress: (blocks done, blocks in all).
  std::vector<FrameImage> render(FrameWindow window, const ChainProgress& progress = {}) const;

 private:
  struct Shot;
  // Calls work(driver) with a chain driver over the window for the method's target.
  template <class Work>
  auto withDriver(FrameWindow window, const Work& work) const;

  const Scene& scene_;
  MetropolisSettings settings_;
  std::unique_ptr<Shot> shot_;
};

}  // namespace pathfarm
