// d re-renders nothing, so its denoise task writes the shot's frame itself (role output)
// instead of handing a frame of features to a composite that would only copy its colors.
// That frame must be the one the composite would have written.
#include <gtest/gtest.h>

#include <map>

#include "image/exr_io.h"
#include "test_support.h"
#include "worker/task_runner.h"

namespace pathfarm::farm {
namespace {

constexpr int kDenoiseSize = 40, kDenoiseSpp = 4;

// Frames 0 to 2 of the Cornell box (the mirror ball moves; the lamp is seen directly).
std::map<std::string, std::string> renderedFrames() {
  std::map<std::string, std::string> chunks;
  for (int64_t frame = 0; frame <= 2; ++frame)
    chunks["render" + std::to_string(frame)] = encodeExr(
        test_support::renderDecomposed("scenes/cornell/scene.json", kDenoiseSize, kDenoiseSize, kDenoiseSpp, frame),
        ExrCompression::Fast);
  return chunks;
}

Lease denoiseLease(TaskRole role) {
  Lease lease;
  lease.set_kind(TASK_DENOISE);
  lease.mutable_spec()->set_pipeline("d");
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
  std::map<std::string, std::string> chunks = renderedFrames();
  TaskRunner runner(1, test_support::processTemporaryFolder("pathfarm_denoise_scenes"),
                    test_support::processTemporaryFolder("pathfarm_denoise_outgoing"));
  std::atomic<double> progress{0};
  std::atomic<bool> abandon{false};
  const TaskRunner::ChunkFetcher fetch = [&](const ChunkRef& ref) { return chunks.at(ref.sha256()); };
  const FrameImage final = decodeExr(runner.run(denoiseLease(ROLE_OUTPUT), fetch, progress, abandon).chunk, "final");

  // The other way: the denoised keyframe with its features, then a composite of it alone.
  chunks["denoised"] = runner.run(denoiseLease(ROLE_UNSPECIFIED), fetch, progress, abandon).chunk;
  Lease composite;
  composite.set_kind(TASK_COMPOSITE);
  composite.mutable_spec()->set_pipeline("d");
  composite.mutable_params()->set_frame(1);
  composite.add_inputs()->set_sha256("denoised");
  composite.add_input_kinds(TASK_DENOISE);
  composite.add_input_params()->set_frame(1);
  const FrameImage expected = decodeExr(runner.run(composite, fetch, progress, abandon).chunk, "composite");

  ASSERT_EQ(final.channelNames(), expected.channelNames());
  EXPECT_FALSE(final.hasChannel("diffuse_direct.normal.X"));  // no features: only what the shot keeps
  for (const std::string& name : expected.channelNames())
    for (size_t p = 0; p < expected.pixelCount(); ++p)
      ASSERT_EQ(final.channel(name)[p], expected.channel(name)[p]) << name << " pixel " << p;
  EXPECT_EQ(final.attributes().at("pathfarm.pipeline"), "d");
  EXPECT_EQ(final.attributes().at("pathfarm.rerender_pixels"), "0");
  // The lamp, seen directly, skips the filter and is back in the frame: the brightest
  // pixel is far above anything the walls reflect.
  float brightest = 0;
  for (const float v : final.channel("G")) brightest = std::max(brightest, v);
  EXPECT_GT(brightest, 5.0f);
}

}  // namespace
}  // namespace pathfarm::farm
