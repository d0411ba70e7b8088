// Intermediate chunks keep only the channels their readers use (worker/chunk_channels.h).
// Checked the other way round: every filter task of a small di and dui shot of the
// walkthrough runs twice, once on inputs with all their channels and once with every
// channel their chunks drop overwritten by junk. A task that read a dropped channel, or
// whose output kept one its input dropped, gives other bytes; a reader of a chunk its
// producer pruned throws, naming the missing channel.
#include <gtest/gtest.h>

#include <map>
#include <string>

#include "image/exr_io.h"
#include "postproc/filters/decomposed_frame.h"
#include "test_support.h"
#include "task_output_bytes.h"
#include "worker/chunk_channels.h"
#include "worker/filter_tasks.h"

namespace pathfarm::farm {
namespace chunk_channels_test {

constexpr int kWidth = 64, kHeight = 36, kShotSpp = 16, kBefore = 0, kFrame = 1, kAfter = 2;

FrameImage render(int64_t frame, int spp, MotionSpan span = {}) {
  return test_support::renderDecomposed("scenes/walkthrough/scene.json", kWidth, kHeight, spp, frame, span);
}

// `frame` with every channel a chunk of `content` drops set to a junk value.
std::shared_ptr<FrameImage> withDroppedChannelsJunk(const FrameImage& frame, ChunkContent content, Pipeline pipeline) {
  FrameImage kept = frame;
  keepReadChannels(content, stagesOf(pipeline), kept);
  auto junk = std::make_shared<FrameImage>(frame);
  for (const std::string& name : junk->channelNames()) {
    if (kept.hasChannel(name)) continue;
    std::vector<float>& values = junk->channel(name);
    for (size_t p = 0; p < values.size(); ++p) values[p] = 7500.0f + static_cast<float>(p % 13);
  }
  return junk;
}

Lease leaseOf(TaskKind kind, Pipeline pipeline, int64_t frame) {
  Lease lease;
  lease.set_kind(kind);
  ShotSpec& spec = *lease.mutable_spec();
  spec.set_width(kWidth);
  spec.set_height(kHeight);
  spec.set_spp(kShotSpp);
  spec.set_tile(16);
  spec.set_pipeline(pipeline);
  spec.set_frame_start(kBefore);
  spec.set_frame_end(kAfter);
  spec.set_keyframe_interval(kAfter - kBefore);
  lease.mutable_params()->set_frame(frame);
  lease.mutable_params()->set_keyframe_before(kBefore);
  lease.mutable_params()->set_keyframe_after(kAfter);
  return lease;
}

TaskInput inputOf(TaskKind kind, int64_t frame, std::shared_ptr<FrameImage> image, const std::string& component = "") {
  TaskParams params;
  params.set_frame(frame);
  params.set_component(component);
  return {kind, params, std::move(image)};
}

std::shared_ptr<FrameImage> decoded(const TaskOutput& output) {
  return std::make_shared<FrameImage>(decodeExr(outputBytes(output), "a task's output"));
}

// What a task gave: its chunk's bytes and the re-render tiles it asked for.
std::string everythingOf(const TaskOutput& output) {
  std::string all = outputBytes(output);
  for (const TaskParams& tile : output.followUps) all += tile.SerializeAsString();
  return all;
}

// One shot's renders, as the farm's render tiles would carry them with all their channels.
struct Renders {
  std::map<int64_t, FrameImage> keyframes;
  FrameImage features, rerendered;
};

Renders renderShot(Pipeline pipeline) {
  const MotionSpan span{kAfter - kBefore, kAfter - kBefore};
  const int keyframeSpp = stagesOf(pipeline).upsample ? kShotSpp / 4 : kShotSpp;
  return {{{kBefore, render(kBefore, keyframeSpp, span)}, {kAfter, render(kAfter, keyframeSpp, span)}},
          render(kFrame, 4),
          render(kFrame, kShotSpp)};
}

// Runs the shot's filter tasks for keyframes kBefore and kAfter and the frame between them
// on `renders`, or on `renders` with their dropped channels junk, and returns each task's
// output by name.
std::map<std::string, std::string> runShot(const Renders& renders, Pipeline pipeline, bool junk) {
  const FilteringStages stages = stagesOf(pipeline);
  auto rendered = [&](const FrameImage& frame, ChunkContent content) {
    return junk ? withDroppedChannelsJunk(frame, content, pipeline) : std::make_shared<FrameImage>(frame);
  };
  std::map<std::string, std::string> outputs;
  std::map<int64_t, std::shared_ptr<FrameImage>> filtered;
  for (const int64_t keyframe : {kBefore, kAfter}) {
    const int64_t other = keyframe == kBefore ? kAfter : kBefore;
    std::vector<TaskInput> inputs = {
        inputOf(TASK_ASSEMBLE_FRAME, keyframe, rendered(renders.keyframes.at(keyframe), ChunkContent::KeyframeRender)),
        inputOf(TASK_ASSEMBLE_FRAME, other, rendered(renders.keyframes.at(other), ChunkContent::KeyframeRender))};
    const TaskOutput denoised = runDenoiseTask(leaseOf(TASK_DENOISE, pipeline, keyframe), inputs);
    outputs["denoise " + std::to_string(keyframe)] = everythingOf(denoised);
    filtered[keyframe] = decoded(denoised);
    if (!stages.upsample) continue;
    inputs = {inputOf(TASK_DENOISE, keyframe, filtered[keyframe]),
              inputOf(TASK_ASSEMBLE_FRAME, keyframe,
                      rendered(renders.keyframes.at(keyframe), ChunkContent::KeyframeRender))};
    const TaskOutput upsampled = runUpsampleTask(leaseOf(TASK_UPSAMPLE, pipeline, keyframe), inputs);
    outputs["upsample " + std::to_string(keyframe)] = everythingOf(upsampled);
    filtered[keyframe] = decoded(upsampled);
  }
  const TaskKind keyframeKind = stages.upsample ? TASK_UPSAMPLE : TASK_DENOISE;
  std::vector<TaskInput> interpolation = {inputOf(keyframeKind, kBefore, filtered[kBefore]),
                                          inputOf(keyframeKind, kAfter, filtered[kAfter]),
                                          inputOf(TASK_ASSEMBLE_FRAME, kFrame,
                                                  rendered(renders.features, ChunkContent::FeatureRender))};
  for (const std::string& component : decompositionComponents(*filtered[kBefore])) {
    Lease lease = leaseOf(TASK_FLOW, pipeline, kFrame);
    lease.mutable_params()->set_component(component);
    std::vector<TaskInput> keyframes = {interpolation[0], interpolation[1]};
    const TaskOutput flow = runFlowTask(lease, keyframes);
    outputs["flow " + component] = everythingOf(flow);
    interpolation.push_back(inputOf(TASK_FLOW, kFrame, decoded(flow), component));
  }
  const TaskOutput interpolated = runInterpolateTask(leaseOf(TASK_INTERPOLATE, pipeline, kFrame), interpolation);
  outputs["interpolate"] = everythingOf(interpolated);
  EXPECT_FALSE(interpolated.followUps.empty()) << "the composite would have no re-rendered pixels to denoise";

  // The composite of the frame, with the re-render tiles the interpolation asked for.
  std::vector<TaskInput> composite = {inputOf(TASK_INTERPOLATE, kFrame, decoded(interpolated))};
  const std::shared_ptr<FrameImage> rerendered = rendered(renders.rerendered, ChunkContent::RerenderedPixels);
  for (const TaskParams& tile : interpolated.followUps) {
    const PixelWindow& w = tile.window();
    composite.push_back({TASK_RENDER_TILE, tile,
                         std::make_shared<FrameImage>(rerendered->crop(w.x0(), w.y0(), w.x1() - w.x0(), w.y1() - w.y0()))});
  }
  outputs["composite"] = everythingOf(runCompositeTask(leaseOf(TASK_COMPOSITE, pipeline, kFrame), composite));
  return outputs;
}

void expectNoTaskReadsADroppedChannel(Pipeline pipeline) {
  const Renders renders = renderShot(pipeline);
  const std::map<std::string, std::string> whole = runShot(renders, pipeline, false);
  const std::map<std::string, std::string> junk = runShot(renders, pipeline, true);
  ASSERT_EQ(whole.size(), junk.size());
  for (const auto& [task, bytes] : whole)
    EXPECT_TRUE(bytes == junk.at(task)) << pipelineName(pipeline) << ": the " << task
                                        << " task's output depends on a channel its inputs drop";
  EXPECT_GT(whole.at("composite").size(), 0u);
}

TEST(ChunkChannels, NoDuiTaskReadsAChannelItsInputsDrop) { expectNoTaskReadsADroppedChannel(PIPELINE_DUI); }

TEST(ChunkChannels, NoDiTaskReadsAChannelItsInputsDrop) { expectNoTaskReadsADroppedChannel(PIPELINE_DI); }

TEST(ChunkChannels, RenderTilesOfFilteredFramesDropTheBuffersNoFilterReads) {
  FrameImage keyframe = render(kBefore, 4);
  ASSERT_TRUE(keyframe.hasChannel("diffuse_direct.uv.X"));
  const size_t before = keyframe.channelNames().size();
  keepReadChannels(*renderedContent(ROLE_KEYFRAME), stagesOf(PIPELINE_DUI), keyframe);
  for (const char* dropped : {"diffuse_direct.uv.X", "diffuse_direct.uv.Y", "diffuse_direct.primid.Y", "variance.R"})
    EXPECT_FALSE(keyframe.hasChannel(dropped)) << dropped;
  for (const char* kept : {"R", "diffuse_direct.color.R", "diffuse_direct.motion.X", "motion.X", "silhouette.Y"})
    EXPECT_TRUE(keyframe.hasChannel(kept)) << kept;
  EXPECT_LT(keyframe.channelNames().size(), before);
  // The frame-wide variance: only an in-between frame's caustic check reads it.
  FrameImage features = render(kBefore, 4);
  keepReadChannels(*renderedContent(ROLE_FEATURES), stagesOf(PIPELINE_DUI), features);
  EXPECT_TRUE(features.hasChannel("variance.R"));
  // References, baselines and pt's own frames keep every channel.
  for (const TaskRole role : {ROLE_REFERENCE, ROLE_BASELINE, ROLE_OUTPUT}) EXPECT_FALSE(renderedContent(role));
}

// A render tile measures motion only for a chunk that keeps some: keyframes, whose motion
// the denoiser and the interpolation follow, and never the features or the re-rendered
// pixels, whose readers read none.
TEST(ChunkChannels, OnlyChunksThatKeepMotionMeasureIt) {
  FrameImage full = render(kBefore, 1);
  for (const Pipeline pipeline : {PIPELINE_D, PIPELINE_DI, PIPELINE_DU, PIPELINE_DUI}) {
    for (const TaskRole role : {ROLE_KEYFRAME, ROLE_FEATURES, ROLE_RERENDER}) {
      FrameImage kept = full;
      keepReadChannels(*renderedContent(role), stagesOf(pipeline), kept);
      bool keepsMotion = false;
      for (const std::string& name : kept.channelNames())
        keepsMotion = keepsMotion || name.find("motion") != std::string::npos || name == "silhouette.Y";
      EXPECT_EQ(readsMotion(*renderedContent(role), stagesOf(pipeline)), keepsMotion)
          << pipelineName(pipeline) << " role " << role;
      EXPECT_EQ(keepsMotion, role == ROLE_KEYFRAME) << pipelineName(pipeline) << " role " << role;
    }
  }
}

// Half floats hold the radiance and the bounded features, each where all of its values
// fit; the variance, motion, depth and ids keep 32 bits.
TEST(ChunkChannels, HalfFloatsHoldTheRadianceAndBoundedFeaturesThatFit) {
  const FrameImage keyframe = render(kBefore, 4);
  const ChannelFilter half = halfPrecisionChannels(keyframe);
  for (const char* name : {"R", "diffuse_direct.color.G", "diffuse_direct.emission.R", "diffuse_direct.irradiance.B",
                           "diffuse_direct.reflectance.R", "diffuse_direct.normal.Z", "diffuse_direct.coverage.Y"}) {
    ASSERT_TRUE(keyframe.hasChannel(name)) << name;
    EXPECT_TRUE(half(name)) << name;
  }
  for (const char* name : {"variance.R", "diffuse_direct.variance.G", "diffuse_direct.motion.X", "motion.X",
                           "depth.Z", "diffuse_direct.objectid.Y"}) {
    ASSERT_TRUE(keyframe.hasChannel(name)) << name;
    EXPECT_FALSE(half(name)) << name;
  }
  // One value beyond a half's range keeps that channel, and that channel alone, in floats.
  FrameImage bright = keyframe;
  bright.channel("diffuse_direct.color.G")[3] = 70000.0f;
  const ChannelFilter brightHalf = halfPrecisionChannels(bright);
  EXPECT_FALSE(brightHalf("diffuse_direct.color.G"));
  EXPECT_TRUE(brightHalf("diffuse_direct.color.R"));
}

}  // namespace chunk_channels_test
}  // namespace pathfarm::farm
