// libFuzzer target for shot files: any bytes, as a shot file in fuzz/assets (so it may
// name the scenes there), must read into a ShotSpec or be refused with a SceneError, which
// `pathfarm submit` and `pathfarm local` report with exit status 2; never crash, hang,
// leak, read out of bounds or allocate without limit. Built and run by bench/fuzz.sh
// (clang, ASan, UBSan).
#include <algorithm>
#include <cstdlib>
#include <memory>
#include <string>

#include "fuzz/fuzz_support.h"
#include "postproc/poisson/screened_poisson.h"
#include "renderer/setup/auto_decomposition.h"
#include "renderer/scene/json_node.h"
#include "client/keyframe_probe.h"
#include "client/reference_pilot.h"
#include "client/shot_preparation.h"

// Three steps of reading and preparing a shot render probes: "decompose": "auto" on a scene
// with glass, "keyframe_interval": "auto" and the pilot of "reference_spp": "auto" (for
// auto's prediction only, but linked). Rendering is not reading, and the renderer (Embree,
// TBB) compiled with sanitizers would cost minutes per CI run; these stand-ins keep
// everything else, and choose what a probe could.
namespace pathfarm {

std::shared_ptr<const Decomposition> decompositionFor(const Scene&, const std::string& spec) {
  if (spec == "none") return nullptr;
  if (spec == "auto") return std::make_shared<Decomposition>(Decomposition::standard());
  return std::make_shared<Decomposition>(Decomposition::parse(spec));
}

// The planner needs window_blend.cpp's planWindows only; its solver is never called while
// a shot is read, and stays out of the fuzzer.
std::vector<GradientFrame::Color> reconstructWindow(const std::vector<const GradientFrame*>&, const PoissonSettings&,
                                                    PoissonStats*) {
  std::abort();
}

namespace farm {

KeyframeChoice chooseKeyframeInterval(const Scene&, const ShotSpec& spec, double, int maxInterval) {
  const int64_t frames = spec.frame_end() - spec.frame_start() + 1;
  const int longest = static_cast<int>(std::min<int64_t>(maxInterval, frames - 1));
  if (longest < 2) return {1, "k = 1: the shot is too short to interpolate any frame"};
  return {longest, "k = " + std::to_string(longest) + ": the fuzzer's stand-in for the probe"};
}

double pilotRelMsePerSample(const Scene&, const ShotSpec&, int64_t) { return 1; }

}  // namespace farm
}  // namespace pathfarm

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  pathfarm::fuzz::silenceLogs();
  try {
    const pathfarm::farm::ShotSpec spec = pathfarm::farm::preparedShot(pathfarm::farm::ShotFile::parse(
        pathfarm::fuzz::asText(data, size), pathfarm::fuzz::assetFolder() / "fuzz-input.shot.json"));
    (void)spec;
  } catch (const pathfarm::SceneError& e) {
    pathfarm::fuzz::noteRefusal(e);
  }
  return 0;
}
