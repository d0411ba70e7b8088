// The irradiance flow of one component reads only that component's channels of its two
// keyframes: decoded alone from the chunk files when the worker would not keep the frames
// decoded (a 1080p keyframe), taken from the decoded frames when it would. Either way the
// flow is the same bits.
#include <gtest/gtest.h>

#include <atomic>

#include "image/exr_io.h"
#include "postproc/filters/decomposed_frame.h"
#include "test_support.h"
#include "worker/task_runner.h"

namespace pathfarm::farm {
namespace {

constexpr int kFlowWidth = 64, kFlowHeight = 36, kKeyframeBefore = 0, kKeyframeAfter = 3;

// The walkthrough's keyframe `frame`, decomposed, with motion reaching the other keyframe
// and the effective irradiance a filtered keyframe carries.
FrameImage keyframe(int64_t frame) {
  const int reach = kKeyframeAfter - kKeyframeBefore;
  FrameImage image =
      test_support::renderDecomposed("scenes/walkthrough/scene.json", kFlowWidth, kFlowHeight, 16, frame, {reach, reach});
  deriveIrradiance(image);
  return image;
}

// The flow chunk of `component` made by a worker that keeps `decodedBytes` of decoded inputs.
std::string flowChunk(const std::map<std::string, std::filesystem::path>& files, const std::string& component,
                      uint64_t decodedBytes) {
  Lease lease;
  lease.set_kind(TASK_FLOW);
  ShotSpec& spec = *lease.mutable_spec();
  spec.set_pipeline(PIPELINE_DUI);
  spec.set_width(kFlowWidth);
  spec.set_height(kFlowHeight);
  TaskParams& params = *lease.mutable_params();
  params.set_frame(kKeyframeBefore);
  params.set_keyframe_before(kKeyframeBefore);
  params.set_keyframe_after(kKeyframeAfter);
  params.set_component(component);
  for (const int64_t frame : {kKeyframeBefore, kKeyframeAfter}) {
    lease.add_inputs()->set_sha256(std::to_string(frame));
    lease.add_input_kinds(TASK_UPSAMPLE);
    lease.add_input_params()->set_frame(frame);
  }
  const auto folder = test_support::processTemporaryFolder("pathfarm_flow_" + std::to_string(decodedBytes));
  TaskRunner runner(1, folder / "scenes", folder / "outgoing", decodedBytes);
  std::atomic<double> progress{0};
  std::atomic<bool> abandon{false};
  return runner
      .run(lease, [](const ChunkRef&) -> std::string { throw std::logic_error("read in place"); }, progress, abandon,
           [&](const ChunkRef& ref) { return files.at(ref.sha256()); })
      .chunk;
}

TEST(FlowTask, AComponentsFlowIsTheSameBitsDecodedAloneOrFromTheWholeFrame) {
  const auto folder = test_support::processTemporaryFolder("pathfarm_flow_inputs");
  std::map<std::string, std::filesystem::path> files;
  for (const int64_t frame : {kKeyframeBefore, kKeyframeAfter}) {
    files[std::to_string(frame)] = folder / (std::to_string(frame) + ".exr");
    writeExr(files[std::to_string(frame)], keyframe(frame));
  }
  for (const std::string component : {"diffuse_direct", "reflection"}) {
    const std::string alone = flowChunk(files, component, 0);  // nothing kept: the component decoded alone
    const std::string whole = flowChunk(files, component, TaskRunner::kDefaultDecodedInputBytes);
    EXPECT_EQ(alone, whole) << component;
    const FrameImage flow = decodeExr(alone, "flow");
    EXPECT_TRUE(flow.hasChannel(component + ".irradiance_forward.X")) << component;
  }
}

}  // namespace
}  // namespace pathfarm::farm
