// The upsample task as a worker runs it, on a walkthrough keyframe rendered with a quarter
// of the shot's samples: its directly seen light goes back into the frame unfiltered, so
// wherever that light is visibly wrong (the gold bowl's glossy highlight of the window,
// the window's edges) the pixel must be sent to re-rendering at the shot's spp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "image/exr_io.h"
#include "postproc/filters/component_upsampler.h"
#include "test_support.h"
#include "task_output_bytes.h"
#include "worker/direct_emission.h"
#include "worker/filter_tasks.h"

namespace pathfarm::farm {
namespace {

constexpr int kUpsampleWidth = 160, kUpsampleHeight = 90, kUpsampleShotSpp = 64, kUpsampleFrame = 12;

FrameImage renderKeyframe(int spp) {
  return test_support::renderDecomposed("scenes/walkthrough/scene.json", kUpsampleWidth, kUpsampleHeight, spp, kUpsampleFrame);
}

// Per pixel, the luminance of the directly seen light, summed over the components.
std::vector<float> directLightLuminance(const FrameImage& frame) {
  const FrameImage light = directEmissionOf(frame);
  std::vector<float> sum(frame.pixelCount(), 0.0f);
  for (const std::string& name : light.channelNames()) {
    const float weight = name.ends_with(".R") ? 0.2126f : name.ends_with(".G") ? 0.7152f : 0.0722f;
    const std::vector<float>& values = light.channel(name);
    for (size_t p = 0; p < sum.size(); ++p) sum[p] += weight * values[p];
  }
  return sum;
}

TEST(UpsampleTask, DirectlySeenLightThatTheKeyframesFewSamplesGetWrongIsReRendered) {
  const auto keyframe = std::make_shared<FrameImage>(renderKeyframe(kUpsampleShotSpp / 4));
  const auto low = std::make_shared<FrameImage>(boxDownsample(*keyframe, 2));
  Lease lease;
  lease.set_kind(TASK_UPSAMPLE);
  ShotSpec& spec = *lease.mutable_spec();
  spec.set_width(kUpsampleWidth);
  spec.set_height(kUpsampleHeight);
  spec.set_spp(kUpsampleShotSpp);
  spec.set_tile(16);
  spec.set_pipeline(PIPELINE_DUI);
  lease.mutable_params()->set_frame(kUpsampleFrame);
  TaskParams params;
  params.set_frame(kUpsampleFrame);
  std::vector<TaskInput> inputs = {{TASK_DENOISE, params, low}, {TASK_ASSEMBLE_FRAME, params, keyframe}};
  const TaskOutput output = runUpsampleTask(lease, inputs);
  const FrameImage result = decodeExr(outputBytes(output), "upsampled keyframe");
  const std::vector<float>& flagged = result.channel("rerender.Y");
  // The upsampler's record of its settings goes with the frame (the keyframe's own
  // attributes stay too).
  EXPECT_EQ(result.attributes().count("pathfarm.upsample"), 1u);
  EXPECT_EQ(result.attributes().count("pathfarm.decomposition"), 1u);

  // Wrong: the keyframe's directly seen light is off from a 256-spp render's by more than
  // a quarter of what the pixel shows there.
  const FrameImage reference = renderKeyframe(256);
  const std::vector<float> light = directLightLuminance(*keyframe), truth = directLightLuminance(reference);
  const std::vector<float>& r = reference.channel("R");
  const std::vector<float>& g = reference.channel("G");
  const std::vector<float>& b = reference.channel("B");
  size_t wrong = 0, wrongFlagged = 0, allFlagged = 0;
  for (size_t p = 0; p < light.size(); ++p) {
    const bool isFlagged = flagged[p] > 0.5f;
    allFlagged += isFlagged;
    const float shown = std::max(0.2126f * r[p] + 0.7152f * g[p] + 0.0722f * b[p], 0.05f);
    if (std::abs(light[p] - truth[p]) <= 0.25f * shown) continue;
    ++wrong;
    wrongFlagged += isFlagged;
  }
  std::printf("directly seen light wrong at %zu pixels, %zu of them flagged; %zu pixels flagged in all\n", wrong,
              wrongFlagged, allFlagged);
  ASSERT_GT(wrong, 10u);  // the window and its glossy highlight are in view
  EXPECT_GE(static_cast<double>(wrongFlagged), 0.9 * static_cast<double>(wrong));
  // The rest of the frame stays upsampled.
  EXPECT_LT(static_cast<double>(allFlagged), 0.1 * static_cast<double>(light.size()));
  EXPECT_EQ(output.metrics.at("rerender_light_edges") > 0, true);
}

}  // namespace
}  // namespace pathfarm::farm
