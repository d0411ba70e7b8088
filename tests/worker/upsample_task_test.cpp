// The upsample task as a worker runs it, on a walkthrough keyframe rendered with a quarter
// of the shot's samples: its directly seen light goes back into the frame unfiltered, so
// wherever that light is visibly wrong (the gold bowl's glossy highlight of the window,
// the window's edges) the pixel must be sent to re-rendering at the shot's spp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>

#include "contract/pipeline.h"
#include "image/exr_io.h"
#include "postproc/filters/component_upsampler.h"
#include "test_support.h"
#include "task_output_bytes.h"
#include "postproc/filters/direct_emission.h"
#include "worker/failure_class.h"
#include "worker/filter_tasks.h"
#include "worker/task_runner.h"

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

// A keyframe upsampled window by window (each task reading only the rows its filters
// reach) and joined is the same bytes, the same re-render and the same counts as the
// keyframe upsampled by one task; read from files by a worker that keeps nothing decoded,
// too. The window borders cut through the walkthrough's walls, furniture and lamps.
TEST(UpsampleTask, WindowsUpsampledApartAndJoinedAreTheWholeFramesBytes) {
  constexpr int kWidth = 64, kHeight = 200;
  const FrameImage keyframe = test_support::renderDecomposed("scenes/walkthrough/scene.json", kWidth, kHeight, 4, 12);
  std::map<std::string, std::string> chunks = {{"render", encodeExr(keyframe, ExrCompression::Fast)},
                                               {"low", encodeExr(boxDownsample(keyframe, 2), ExrCompression::Fast)}};
  Lease whole;
  whole.set_kind(TASK_UPSAMPLE);
  ShotSpec& spec = *whole.mutable_spec();
  spec.set_width(kWidth);
  spec.set_height(kHeight);
  spec.set_spp(16);
  spec.set_tile(16);
  spec.set_pipeline(PIPELINE_DUI);
  spec.set_filter_window_rows(64);
  whole.mutable_params()->set_frame(12);
  const auto addInput = [](Lease& lease, const std::string& name, TaskKind kind, const TaskParams& params) {
    lease.add_inputs()->set_sha256(name);
    lease.add_input_kinds(kind);
    *lease.add_input_params() = params;
  };
  const Lease noInputs = whole;
  TaskParams params;
  params.set_frame(12);
  addInput(whole, "low", TASK_DENOISE, params);
  addInput(whole, "render", TASK_ASSEMBLE_FRAME, params);

  TaskRunner runner(1, test_support::processTemporaryFolder("pathfarm_upsample_scenes"),
                    test_support::processTemporaryFolder("pathfarm_upsample_outgoing"));
  const auto folder = test_support::processTemporaryFolder("pathfarm_upsample_files");
  TaskRunner fromFiles(1, folder / "scenes", folder / "outgoing", 0);
  std::atomic<double> progress{0};
  std::atomic<bool> abandon{false};
  const auto run = [&](const Lease& lease) {
    return runner.run(lease, [&](const ChunkRef& ref) { return chunks.at(ref.sha256()); }, progress, abandon);
  };
  const auto runFromFiles = [&](const Lease& lease) {
    return fromFiles.run(
        lease, [](const ChunkRef&) -> std::string { throw std::logic_error("read in place"); }, progress, abandon,
        [&](const ChunkRef& ref) {
          const std::filesystem::path file = folder / (ref.sha256() + ".exr");
          if (!std::filesystem::exists(file)) std::ofstream(file, std::ios::binary) << chunks.at(ref.sha256());
          return file;
        });
  };
  const TaskOutput one = run(whole);
  const std::string expected = outputBytes(one);

  const std::vector<RowWindow> windows = filterWindowsOf(spec);
  ASSERT_EQ(windows.size(), 4u);
  Lease join = noInputs;
  std::map<std::string, double> summed;
  for (const RowWindow& rows : windows) {
    Lease part = windowOf(noInputs, rows);
    addInput(part, "low", TASK_DENOISE, params);
    addInput(part, "render", TASK_ASSEMBLE_FRAME, params);
    const TaskOutput output = run(part);
    EXPECT_TRUE(output.followUps.empty()) << "a window's re-render goes with the join's";
    for (const auto& [name, value] : output.metrics) summed[name] += value;
    const std::string name = "window" + std::to_string(rows.first);
    chunks[name] = outputBytes(output);
    EXPECT_TRUE(outputBytes(runFromFiles(part)) == chunks[name]) << "rows " << rows.first << " read from the file";
    addInput(join, name, TASK_UPSAMPLE, part.params());
  }
  const TaskOutput joined = run(join);
  EXPECT_TRUE(outputBytes(joined) == expected) << "the joined windows differ from the whole frame's upsample";
  EXPECT_TRUE(outputBytes(runFromFiles(join)) == expected) << "joined from files";
  ASSERT_EQ(joined.followUps.size(), one.followUps.size());
  ASSERT_GT(one.followUps.size(), 0u) << "nothing to re-render: the test would not see the join's";
  for (size_t t = 0; t < one.followUps.size(); ++t)
    EXPECT_EQ(joined.followUps[t].SerializeAsString(), one.followUps[t].SerializeAsString()) << "re-render tile " << t;
  EXPECT_EQ(joined.metrics.at("rerender_pixels"), one.metrics.at("rerender_pixels"));
  EXPECT_EQ(summed.at("rerender_light_edges"), one.metrics.at("rerender_light_edges"));
  EXPECT_EQ(summed.at("rerender_moving_caustics"), one.metrics.at("rerender_moving_caustics"));
}

TEST(UpsampleTask, AJoinOfWindowsThatLeaveRowsOutIsRefused) {
  constexpr int kWidth = 8, kHeight = 8;
  Lease join;
  join.set_kind(TASK_UPSAMPLE);
  join.mutable_spec()->set_width(kWidth);
  join.mutable_spec()->set_height(kHeight);
  join.mutable_spec()->set_pipeline(PIPELINE_DUI);
  join.mutable_params()->set_frame(0);
  FrameImage rows(kWidth, 4);
  rows.addChannel("rerender.Y");
  TaskParams params;
  params.set_frame(0);
  params.mutable_window()->set_x1(kWidth);
  params.mutable_window()->set_y1(4);
  std::vector<TaskInput> inputs = {{TASK_UPSAMPLE, params, std::make_shared<FrameImage>(rows)}};
  try {
    runUpsampleTask(join, inputs);
    FAIL() << "a join of rows 0-4 of 8 was accepted";
  } catch (const BadInput& e) {
    EXPECT_NE(std::string(e.what()).find("do not cover the frame's rows once each"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace pathfarm::farm
