// d re-renders nothing, so its denoise task writes the shot's frame itself (role output)
// instead of handing a frame of features to a composite that would only copy its colors.
// That frame must be the one the composite would have written.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>

#include "image/exr_io.h"
#include "postproc/filters/component_denoiser.h"
#include "postproc/metrics/image_metrics.h"
#include "renderer/integrators/frame_renderer.h"
#include "renderer/scene/scene_loader.h"
#include "test_support.h"
#include "task_output_bytes.h"
#include "postproc/filters/direct_emission.h"
#include "contract/pipeline.h"
#include "worker/chunk_channels.h"
#include "worker/task_runner.h"

namespace pathfarm::farm {
namespace {

// Frames 0 to 2 of the Cornell box (the mirror ball moves; the lamp is seen directly).
std::map<std::string, std::string> renderedFrames(int size, int spp) {
  std::map<std::string, std::string> chunks;
  for (int64_t frame = 0; frame <= 2; ++frame)
    chunks["render" + std::to_string(frame)] =
        encodeExr(test_support::renderDecomposed("scenes/cornell/scene.json", size, size, spp, frame),
                  ExrCompression::Fast);
  return chunks;
}

FrameImage runTask(const Lease& lease, const std::map<std::string, std::string>& chunks) {
  TaskRunner runner(1, test_support::processTemporaryFolder("pathfarm_denoise_scenes"),
                    test_support::processTemporaryFolder("pathfarm_denoise_outgoing"));
  std::atomic<double> progress{0};
  std::atomic<bool> abandon{false};
  return decodeExr(
      outputBytes(runner.run(lease, [&](const ChunkRef& ref) { return chunks.at(ref.sha256()); }, progress, abandon)),
      TaskKind_Name(lease.kind()));
}

Lease denoiseLease(TaskRole role) {
  Lease lease;
  lease.set_kind(TASK_DENOISE);
  lease.mutable_spec()->set_pipeline(PIPELINE_D);
  lease.mutable_spec()->set_frame_start(0);
  lease.mutable_spec()->set_frame_end(2);
  lease.mutable_params()->set_frame(1);
  lease.mutable_params()->set_role(role);
  for (int64_t frame = 0; frame <= 2; ++frame) {
    lease.add_inputs()->set_sha256("render" + std::to_string(frame));
    lease.add_input_kinds(TASK_ASSEMBLE_FRAME);
    lease.add_input_params()->set_frame(frame);
  }
  return lease;
}

TEST(DenoiseTask, DsFinalFrameIsTheOneACompositeOfItsDenoisedFrameWrites) {
  std::map<std::string, std::string> chunks = renderedFrames(40, 4);
  const FrameImage final = runTask(denoiseLease(ROLE_OUTPUT), chunks);

  // The other way: the denoised keyframe with its features, then a composite of it alone.
  const FrameImage denoised = runTask(denoiseLease(ROLE_UNSPECIFIED), chunks);
  // It carries the filter's record of what it did, as the final frame does.
  for (const char* record : {"pathfarm.denoise", "pathfarm.denoise_skipped", "pathfarm.denoise_fireflies"})
    EXPECT_EQ(denoised.attributes().count(record), 1u) << record;
  EXPECT_EQ(denoised.attributes().at("pathfarm.denoise"), final.attributes().at("pathfarm.denoise"));
  chunks["denoised"] = encodeExr(denoised, ExrCompression::Fast);
  Lease composite;
  composite.set_kind(TASK_COMPOSITE);
  composite.mutable_spec()->set_pipeline(PIPELINE_D);
  composite.mutable_spec()->set_width(40);
  composite.mutable_spec()->set_height(40);
  composite.mutable_params()->set_frame(1);
  composite.add_inputs()->set_sha256("denoised");
  composite.add_input_kinds(TASK_DENOISE);
  composite.add_input_params()->set_frame(1);
  const FrameImage expected = runTask(composite, chunks);

  ASSERT_EQ(final.channelNames(), expected.channelNames());
  EXPECT_FALSE(final.hasChannel("diffuse_direct.normal.X"));  // no features: only what the shot keeps
  // The same light, but for the denoised chunk's half floats: the composite sums a handful
  // of components, each rounded by at most 2^-11 of itself (2^-25 below 2^-14), so by no
  // more than 2^-11 of their sum (with room for the sums' own float rounding) and 2^-22.
  for (const std::string& name : expected.channelNames())
    for (size_t p = 0; p < expected.pixelCount(); ++p) {
      const float value = final.channel(name)[p];
      ASSERT_NEAR(value, expected.channel(name)[p], 1.01f * std::exp2(-11.0f) * value + std::exp2(-22.0f))
          << name << " pixel " << p;
    }
  EXPECT_EQ(final.attributes().at("pathfarm.pipeline"), "d");
  EXPECT_EQ(final.attributes().at("pathfarm.rerender_pixels"), "0");
  // The lamp, seen directly, skips the filter and is back in the frame: the brightest
  // pixel is far above anything the walls reflect.
  float brightest = 0;
  for (const float v : final.channel("G")) brightest = std::max(brightest, v);
  EXPECT_GT(brightest, 5.0f);
}

// Keyframes rendered at the shot's full spp are filtered with a variance cancellation of 1
// (denoise_task.cpp): their filter's bias outweighs its leftover noise. Against an
// independent 512-spp render, the d frame must err less than the same filter with the
// paper's cancellation of 4, and both far less than the unfiltered render.
// Frame 1 of the Cornell box at 512 spp, with samples of its own.
FrameImage cornellReference(int size) {
  RenderSettings settings;
  settings.width = settings.height = size;
  settings.spp = 512;
  settings.maxDepth = 6;
  settings.firstSample = kIndependentFirstSample;
  return FrameRenderer(loadScene(test_support::sourceDir() / "scenes/cornell/scene.json"), settings).render(1);
}

TEST(DenoiseTask, DsFullSampleKeyframesErrLessThanWithThePapersCancellation) {
  constexpr int kSize = 64, kSpp = 64;
  const std::map<std::string, std::string> chunks = renderedFrames(kSize, kSpp);
  const FrameImage final = runTask(denoiseLease(ROLE_OUTPUT), chunks);
  const FrameImage reference = cornellReference(kSize);

  std::map<int64_t, FrameImage> frames;
  for (int64_t frame = 0; frame <= 2; ++frame) {
    frames[frame] = decodeExr(chunks.at("render" + std::to_string(frame)), "render");
    takeDirectEmission(frames[frame]);
  }
  const FrameImage emission = directEmissionOf(decodeExr(chunks.at("render1"), "render"));
  DenoiseSettings paper;
  paper.alpha = 4.0f;
  FrameImage papers = denoiseFrame(frames[1], &frames[0], &frames[2], paper);
  addDirectEmission(papers, emission);

  const std::vector<std::string> beauty = {"R", "G", "B"};
  const double withOne = compareImages(final, reference, beauty).relMse;
  const double withFour = compareImages(papers, reference, beauty).relMse;
  const double unfiltered = compareImages(decodeExr(chunks.at("render1"), "render"), reference, beauty).relMse;
  EXPECT_LT(withOne, withFour) << "cancellation 1: " << withOne << ", 4: " << withFour;
  EXPECT_LT(withFour, 0.5 * unfiltered) << "cancellation 4: " << withFour << ", unfiltered: " << unfiltered;
}

// The farm's keyframe chunks hold the radiance and the bounded features in half floats
// (worker/chunk_channels.h). What that changes in d's frame must be far below the frame's
// own error: under a ten-thousandth of its relMSE against an independent 512-spp render.
TEST(DenoiseTask, KeyframesInHalfFloatsChangeDsFrameByUnderATenThousandthOfItsError) {
  constexpr int kSize = 64, kSpp = 64;
  const std::map<std::string, std::string> chunks = renderedFrames(kSize, kSpp);
  std::map<std::string, std::string> halfChunks;
  for (const auto& [name, bytes] : chunks) {
    const FrameImage frame = decodeExr(bytes, name);
    halfChunks[name] = encodeExr(frame, ExrCompression::Fast, halfPrecisionChannels(frame));
    EXPECT_LT(halfChunks[name].size(), bytes.size() * 3 / 4) << name;
  }
  const FrameImage fromFloats = runTask(denoiseLease(ROLE_OUTPUT), chunks);
  const FrameImage fromHalves = runTask(denoiseLease(ROLE_OUTPUT), halfChunks);
  const std::vector<std::string> beauty = {"R", "G", "B"};
  const double error = compareImages(fromFloats, cornellReference(kSize), beauty).relMse;
  const double change = compareImages(fromHalves, fromFloats, beauty).relMse;
  std::printf("d's frame from half-float keyframes: relMSE change %.3g, against the reference %.3g\n", change, error);
  EXPECT_GT(change, 0.0) << "the half floats changed nothing";
  EXPECT_LT(change, 1e-4 * error) << "relMSE against the reference " << error << ", change " << change;
}

// A keyframe denoised window by window (each task reading the rows its filter reaches, of
// it and of its neighbours where its motion leads) and joined is the same bytes as the
// keyframe denoised by one task: d's final frame, and dui's half-resolution keyframe; read
// from files by a worker that keeps nothing decoded, too. The walkthrough's camera moves,
// and its lamps make fireflies, whose spread crosses the window borders.
TEST(DenoiseTask, WindowsDenoisedApartAndJoinedAreTheWholeFramesBytes) {
  constexpr int kWidth = 32, kHeight = 600, kFrame = 12;
  std::map<std::string, std::string> chunks;
  for (int64_t frame = kFrame - 2; frame <= kFrame + 2; ++frame)
    chunks["render" + std::to_string(frame)] = encodeExr(
        test_support::renderDecomposed("scenes/walkthrough/scene.json", kWidth, kHeight, 4, frame), ExrCompression::Fast);
  const auto folder = test_support::processTemporaryFolder("pathfarm_denoise_windows");
  TaskRunner runner(1, folder / "scenes", folder / "outgoing");
  TaskRunner fromFiles(1, folder / "scenes", folder / "outgoing", 0);
  std::atomic<double> progress{0};
  std::atomic<bool> abandon{false};
  const auto run = [&](const Lease& lease, bool files) {
    if (!files) return runner.run(lease, [&](const ChunkRef& ref) { return chunks.at(ref.sha256()); }, progress, abandon);
    return fromFiles.run(
        lease, [](const ChunkRef&) -> std::string { throw std::logic_error("read in place"); }, progress, abandon,
        [&](const ChunkRef& ref) {
          const std::filesystem::path file = folder / (ref.sha256() + ".exr");
          std::ofstream(file, std::ios::binary) << chunks.at(ref.sha256());
          return file;
        });
  };
  const auto addInput = [](Lease& lease, const std::string& name, TaskKind kind, const TaskParams& params) {
    lease.add_inputs()->set_sha256(name);
    lease.add_input_kinds(kind);
    *lease.add_input_params() = params;
  };
  for (const Pipeline pipeline : {PIPELINE_D, PIPELINE_DUI}) {
    SCOPED_TRACE(pipelineName(pipeline));
    const int interval = pipeline == PIPELINE_DUI ? 2 : 1;
    Lease noInputs;
    noInputs.set_kind(TASK_DENOISE);
    ShotSpec& spec = *noInputs.mutable_spec();
    spec.set_width(kWidth);
    spec.set_height(kHeight);
    spec.set_spp(16);
    spec.set_tile(16);
    spec.set_pipeline(pipeline);
    spec.set_frame_start(kFrame - interval);
    spec.set_frame_end(kFrame + interval);
    spec.set_keyframe_interval(interval);
    spec.set_filter_window_rows(150);
    noInputs.mutable_params()->set_frame(kFrame);
    noInputs.mutable_params()->set_role(pipeline == PIPELINE_D ? ROLE_OUTPUT : ROLE_UNSPECIFIED);
    const auto withRenders = [&](Lease lease) {
      for (int64_t frame = kFrame - interval; frame <= kFrame + interval; frame += interval) {
        TaskParams params;
        params.set_frame(frame);
        addInput(lease, "render" + std::to_string(frame), TASK_ASSEMBLE_FRAME, params);
      }
      return lease;
    };
    const std::string expected = outputBytes(run(withRenders(noInputs), false));
    const FrameImage whole = decodeExr(expected, "the whole frame's denoise");
    ASSERT_NE(whole.attributes().at("pathfarm.denoise_fireflies"), "0") << "no firefly: their spread is not tried";

    const std::vector<RowWindow> windows = filterWindowsOf(spec);
    ASSERT_EQ(windows.size(), 4u);
    Lease join = noInputs;
    for (const RowWindow& rows : windows) {
      const Lease part = withRenders(windowOf(noInputs, rows));
      const TaskOutput output = run(part, false);
      const std::string name = std::string(pipelineName(pipeline)) + "window" + std::to_string(rows.first);
      chunks[name] = outputBytes(output);
      EXPECT_TRUE(outputBytes(run(part, true)) == chunks[name]) << "rows " << rows.first << " read from files";
      addInput(join, name, TASK_DENOISE, part.params());
    }
    EXPECT_TRUE(outputBytes(run(join, false)) == expected) << "the joined windows differ from the whole frame's";
    EXPECT_TRUE(outputBytes(run(join, true)) == expected) << "joined from files";
  }
}

}  // namespace
}  // namespace pathfarm::farm
