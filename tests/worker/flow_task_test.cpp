// The irradiance flow of one component reads only that component's channels of its two
// keyframes, a band of rows at a time: decoded alone from the chunk files when the worker
// would not keep the frames decoded (a 1080p keyframe), taken from the decoded frames when
// it would. Either way, and flowed in windows of rows and joined, the flow is the same bits.
#include <gtest/gtest.h>

#include <atomic>
#include <fstream>

#include "image/exr_io.h"
#include "postproc/filters/decomposed_frame.h"
#include "postproc/interpolation/irradiance_flow.h"
#include "test_support.h"
#include "worker/failure_class.h"
#include "worker/task_output_bytes.h"
#include "worker/task_runner.h"

namespace pathfarm::farm {
namespace {

constexpr int kFlowWidth = 64, kFlowHeight = 36, kKeyframeBefore = 0, kKeyframeAfter = 3;

// The walkthrough's keyframe `frame`, decomposed, with motion reaching the other keyframe
// and the effective irradiance a filtered keyframe carries.
FrameImage keyframe(int64_t frame, int width = kFlowWidth, int height = kFlowHeight) {
  const int reach = kKeyframeAfter - kKeyframeBefore;
  FrameImage image =
      test_support::renderDecomposed("scenes/walkthrough/scene.json", width, height, 16, frame, {reach, reach});
  deriveIrradiance(image);
  return image;
}

// Both keyframes, written to files in `folder`, by the names the leases give their inputs.
std::map<std::string, std::filesystem::path> keyframeFiles(const std::filesystem::path& folder, int width, int height) {
  std::map<std::string, std::filesystem::path> files;
  for (const int64_t frame : {kKeyframeBefore, kKeyframeAfter}) {
    files[std::to_string(frame)] = folder / (std::to_string(frame) + ".exr");
    writeExr(files[std::to_string(frame)], keyframe(frame, width, height));
  }
  return files;
}

// A flow task of `component` for a dui shot of width x height, without inputs.
Lease flowLease(const std::string& component, int width, int height) {
  Lease lease;
  lease.set_kind(TASK_FLOW);
  ShotSpec& spec = *lease.mutable_spec();
  spec.set_pipeline(PIPELINE_DUI);
  spec.set_width(width);
  spec.set_height(height);
  TaskParams& params = *lease.mutable_params();
  params.set_frame(kKeyframeBefore);
  params.set_keyframe_before(kKeyframeBefore);
  params.set_keyframe_after(kKeyframeAfter);
  params.set_component(component);
  return lease;
}

// The lease with the two keyframes (joined upsamples) as its inputs.
Lease withKeyframes(Lease lease) {
  for (const int64_t frame : {kKeyframeBefore, kKeyframeAfter}) {
    lease.add_inputs()->set_sha256(std::to_string(frame));
    lease.add_input_kinds(TASK_UPSAMPLE);
    lease.add_input_params()->set_frame(frame);
  }
  return lease;
}

// The output chunk of `lease` run by a worker that keeps `decodedBytes` of decoded inputs,
// its inputs read from `files`.
std::string flowChunk(const Lease& lease, const std::map<std::string, std::filesystem::path>& files,
                      uint64_t decodedBytes) {
  const auto folder = test_support::processTemporaryFolder("pathfarm_flow_" + std::to_string(decodedBytes));
  TaskRunner runner(1, folder / "scenes", folder / "outgoing", decodedBytes);
  std::atomic<double> progress{0};
  std::atomic<bool> abandon{false};
  return outputBytes(runner.run(
      lease, [](const ChunkRef&) -> std::string { throw std::logic_error("read in place"); }, progress, abandon,
      [&](const ChunkRef& ref) { return files.at(ref.sha256()); }));
}

TEST(FlowTask, AComponentsFlowIsTheSameBitsDecodedAloneOrFromTheWholeFrame) {
  const auto files = keyframeFiles(test_support::processTemporaryFolder("pathfarm_flow_inputs"), kFlowWidth, kFlowHeight);
  for (const std::string component : {"diffuse_direct", "reflection"}) {
    const Lease lease = withKeyframes(flowLease(component, kFlowWidth, kFlowHeight));
    const std::string alone = flowChunk(lease, files, 0);  // nothing kept: the component decoded alone
    const std::string whole = flowChunk(lease, files, TaskRunner::kDefaultDecodedInputBytes);
    EXPECT_EQ(alone, whole) << component;
    const FrameImage flow = decodeExr(alone, "flow");
    EXPECT_TRUE(flow.hasChannel(component + ".irradiance_forward.X")) << component;
  }
}

// With the default filter windows, each flow window solves one band: the windows are the
// bands (so no window solves a band another window solves too).
TEST(FlowTask, TheDefaultFilterWindowsAreTheFlowsBands) {
  for (const int height : {513, 777, 1080, 1100, 2160, 4321}) {
    ShotSpec spec;
    spec.set_height(height);
    const std::vector<RowWindow> windows = filterWindowsOf(spec);
    const std::vector<FlowBand> bands = flowBandsOf(height);
    ASSERT_EQ(windows.size(), bands.size()) << height;
    for (size_t i = 0; i < bands.size(); ++i) {
      EXPECT_EQ(windows[i].first, bands[i].first) << height;
      EXPECT_EQ(windows[i].end, bands[i].end) << height;
    }
  }
}

// A keyframe pair taller than a flow band (irradiance_flow.h: two bands of 300 rows here),
// flowed in three windows of 200 rows (the middle one across the bands' border) and
// joined, is the bytes of the pair flowed by one task.
TEST(FlowTask, WindowsFlowedApartAndJoinedAreTheWholeFramesBytes) {
  constexpr int kNarrow = 32, kTall = 600;
  const auto folder = test_support::processTemporaryFolder("pathfarm_flow_windows");
  auto files = keyframeFiles(folder, kNarrow, kTall);
  const std::string component = "diffuse_direct";
  Lease whole = withKeyframes(flowLease(component, kNarrow, kTall));
  whole.mutable_spec()->set_filter_window_rows(200);
  const std::string expected = flowChunk(whole, files, TaskRunner::kDefaultDecodedInputBytes);

  const std::vector<RowWindow> windows = filterWindowsOf(whole.spec());
  ASSERT_EQ(windows.size(), 3u);
  Lease join = flowLease(component, kNarrow, kTall);
  *join.mutable_spec() = whole.spec();
  for (const RowWindow& rows : windows) {
    const Lease part = windowOf(whole, rows);
    const std::string name = "window" + std::to_string(rows.first);
    files[name] = folder / (name + ".exr");
    std::ofstream(files[name], std::ios::binary) << flowChunk(part, files, rows.first == 0 ? 0 : TaskRunner::kDefaultDecodedInputBytes);
    join.add_inputs()->set_sha256(name);
    join.add_input_kinds(TASK_FLOW);
    *join.add_input_params() = part.params();
  }
  EXPECT_TRUE(flowChunk(join, files, 0) == expected) << "the joined windows differ from the pair's flow";
  // A window of another component is not the join's.
  join.mutable_input_params(1)->set_component("reflection");
  EXPECT_THROW(flowChunk(join, files, 0), BadInput);
}

// Keyframes of another size than the shot's are refused, with both sizes named.
TEST(FlowTask, KeyframesOfAnotherSizeAreRefused) {
  const auto files = keyframeFiles(test_support::processTemporaryFolder("pathfarm_flow_sizes"), kFlowWidth, kFlowHeight);
  for (const auto& [width, height] : {std::pair{kFlowWidth, kFlowHeight + 2}, std::pair{kFlowWidth - 2, kFlowHeight}})
    for (const uint64_t decodedBytes : {uint64_t{0}, TaskRunner::kDefaultDecodedInputBytes}) {
      try {
        flowChunk(withKeyframes(flowLease("diffuse_direct", width, height)), files, decodedBytes);
        ADD_FAILURE() << width << "x" << height << " accepted";
      } catch (const BadInput& e) {
        EXPECT_NE(std::string(e.what()).find("keyframe 0 is 64x36, the shot " + std::to_string(width) + "x" +
                                             std::to_string(height)),
                  std::string::npos)
            << e.what();
      }
    }
}

}  // namespace
}  // namespace pathfarm::farm
