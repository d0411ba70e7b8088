// The interpolate task as a worker runs it, on the walkthrough (keyframes 0 and 3, frame
// 1), whose camera turns left: light the frame's own render sees changed is re-rendered,
// also at the left edge, where the turn brings in what the earlier keyframe never saw and
// the interpolation itself no longer masks light it cannot compare
// (InterpolationSettings::unknownChangeMasks is off in the task: the radiance check
// compares such light with the frame's render).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>

#include "contract/pipeline.h"
#include "image/exr_io.h"
#include "postproc/filters/decomposed_frame.h"
#include "postproc/interpolation/frame_interpolation.h"
#include "task_output_bytes.h"
#include "test_support.h"
#include "postproc/filters/direct_emission.h"
#include "worker/filter_inputs.h"
#include "worker/filter_tasks.h"
#include "worker/task_runner.h"

namespace pathfarm::farm {
namespace {

constexpr int kWidth = 96, kHeight = 54, kBefore = 0, kFrame = 1, kAfter = 3;
constexpr int kStrip = 8;  // the changed columns at the left edge

FrameImage render(int64_t frame, int spp, MotionSpan span, int width = kWidth, int height = kHeight) {
  return test_support::renderDecomposed("scenes/walkthrough/scene.json", width, height, spp, frame, span);
}

// Scales every light buffer of the left strip: a lamp out of view switched on there.
FrameImage withBrighterStrip(FrameImage frame, float factor) {
  for (const std::string& name : frame.channelNames()) {
    const bool light = name == "R" || name == "G" || name == "B" || name.find(".color.") != std::string::npos ||
                       name.find(".irradiance.") != std::string::npos;
    const bool variance = name.rfind("variance.", 0) == 0 || name.find(".variance.") != std::string::npos;
    if (!light && !variance) continue;
    std::vector<float>& values = frame.channel(name);
    for (int y = 0; y < kHeight; ++y)
      for (int x = 0; x < kStrip; ++x) values[static_cast<size_t>(y * kWidth + x)] *= light ? factor : factor * factor;
  }
  return frame;
}

// An interpolate lease of frame kFrame between kBefore and kAfter, without inputs.
Lease interpolateLease() {
  Lease lease;
  lease.set_kind(TASK_INTERPOLATE);
  ShotSpec& spec = *lease.mutable_spec();
  spec.set_width(kWidth);
  spec.set_height(kHeight);
  spec.set_spp(16);
  spec.set_tile(16);
  spec.set_pipeline(PIPELINE_DUI);
  lease.mutable_params()->set_frame(kFrame);
  lease.mutable_params()->set_keyframe_before(kBefore);
  lease.mutable_params()->set_keyframe_after(kAfter);
  return lease;
}

// The share of the strip's pixels the task sends to re-rendering.
double stripFlagged(const std::shared_ptr<FrameImage>& k0, const std::shared_ptr<FrameImage>& k1,
                    const FrameImage& features) {
  const Lease lease = interpolateLease();
  auto input = [](TaskKind kind, int64_t frame, std::shared_ptr<FrameImage> image) {
    TaskParams params;
    params.set_frame(frame);
    return TaskInput{kind, params, std::move(image)};
  };
  std::vector<TaskInput> inputs = {input(TASK_UPSAMPLE, kBefore, k0), input(TASK_UPSAMPLE, kAfter, k1),
                                   input(TASK_ASSEMBLE_FRAME, kFrame, std::make_shared<FrameImage>(features))};
  const FrameImage result = decodeExr(outputBytes(runInterpolateTask(lease, inputs)), "interpolated frame");
  const std::vector<float>& flagged = result.channel("rerender.Y");
  size_t count = 0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kStrip; ++x) count += flagged[static_cast<size_t>(y * kWidth + x)] > 0.5f;
  return static_cast<double>(count) / (kStrip * kHeight);
}

TEST(InterpolateTask, LightThatChangedAtTheEdgeTheCameraTurnsToIsReRendered) {
  const MotionSpan span{kAfter - kBefore, kAfter - kBefore};
  const auto k0 = std::make_shared<FrameImage>(render(kBefore, 64, span));
  const auto k1 = std::make_shared<FrameImage>(render(kAfter, 64, span));
  // The pipeline's feature render has 4 spp. On these walls that is too few to see a light
  // tripled over the strip (window noise above the change: 3 % of the strip flagged, as
  // with no change; 8 spp: 32 %, 16 spp: 94 %). This test checks that the task compares
  // at all, so its render has samples enough for the change to be detectable.
  const FrameImage features = render(kFrame, 32, MotionSpan{});
  const double unchanged = stripFlagged(k0, k1, features);
  const double changed = stripFlagged(k0, k1, withBrighterStrip(features, 3.0f));
  std::printf("re-rendered share of the left strip: unchanged light %.3f, light tripled %.3f\n", unchanged, changed);
  EXPECT_GT(changed, 0.9);
  // Left to the radiance check, the strip is not re-rendered wholesale when nothing changed.
  EXPECT_LT(unchanged, 0.5);
}

// The walkthrough's keyframes kBefore and kAfter, frame kFrame's features and an irradiance
// flow for one component (made up, but valid: 1.5 columns and `flowDy` rows forward and
// back), in files, and an interpolate lease reading them; width x height pixels.
struct InterpolationFiles {
  FrameImage k0, k1, features;
  std::string flowing;
  MotionField field;
  std::filesystem::path folder;
  std::map<std::string, std::filesystem::path> files;
  Lease lease = interpolateLease();

  // The keyframes have `keyframeSpp`; the features `featureSpp`, their reflectance
  // `reflectanceSpp` (0: featureSpp): with as many as the planner gives them
  // (ownReflectanceSpp), it modulates the interpolated irradiance at texture edges.
  InterpolationFiles(const std::string& name, float flowDy, int width = kWidth, int height = kHeight,
                     int featureSpp = 8, int reflectanceSpp = 0, int keyframeSpp = 8) {
    const MotionSpan span{kAfter - kBefore, kAfter - kBefore};
    k0 = render(kBefore, keyframeSpp, span, width, height);
    k1 = render(kAfter, keyframeSpp, span, width, height);
    features = test_support::renderDecomposed("scenes/walkthrough/scene.json", width, height, featureSpp, kFrame, {},
                                              reflectanceSpp);
    lease.mutable_spec()->set_width(width);
    lease.mutable_spec()->set_height(height);
    folder = test_support::processTemporaryFolder(name);
    files = {{"k0", folder / "k0.exr"}, {"k1", folder / "k1.exr"}, {"features", folder / "features.exr"},
             {"flow", folder / "flow.exr"}};
    writeExr(files["k0"], k0);
    writeExr(files["k1"], k1);
    writeExr(files["features"], features);
    addInput(lease, "k0", TASK_UPSAMPLE, kBefore, "");
    addInput(lease, "k1", TASK_UPSAMPLE, kAfter, "");
    addInput(lease, "features", TASK_ASSEMBLE_FRAME, kFrame, "");
    flowing = decompositionComponents(k0).front();
    FrameImage flow(width, height);
    field = MotionField{width, height, std::vector<float>(k0.pixelCount(), 1.5f),
                        std::vector<float>(k0.pixelCount(), flowDy), std::vector<float>(k0.pixelCount(), 1.0f)};
    writeMotionField(flow, flowing + ".irradiance_forward", field);
    writeMotionField(flow, flowing + ".irradiance_backward", field);
    writeExr(files["flow"], flow);
    addInput(lease, "flow", TASK_FLOW, kBefore, flowing);
  }

  static void addInput(Lease& lease, const std::string& name, TaskKind kind, int64_t frame, const std::string& component) {
    lease.add_inputs()->set_sha256(name);
    lease.add_input_kinds(kind);
    TaskParams& params = *lease.add_input_params();
    params.set_frame(frame);
    params.set_component(component);
    if (kind == TASK_INTERPOLATE) {
      params.set_keyframe_before(kBefore);
      params.set_keyframe_after(kAfter);
    }
  }

  // Runs `task` on a worker with two threads (components are read and interpolated two at
  // a time, as on a worker) keeping `decodedBytes` of decoded inputs.
  TaskOutput run(const Lease& task, uint64_t decodedBytes) const {
    TaskRunner runner(2, folder / "scenes", folder / ("outgoing" + std::to_string(decodedBytes)), decodedBytes);
    std::atomic<double> progress{0};
    std::atomic<bool> abandon{false};
    return runner.run(task, [](const ChunkRef&) -> std::string { throw std::logic_error("read in place"); }, progress,
                      abandon, [&](const ChunkRef& ref) { return files.at(ref.sha256()); });
  }
};

// The files' keyframes interpolated whole, as the task does (their directly seen light taken
// out, every component's motion at once), modulated by the features' reflectance when
// `ownReflectance`.
InterpolationResult wholeInterpolation(const InterpolationFiles& in, bool ownReflectance) {
  FrameImage w0 = in.k0, w1 = in.k1;
  takeDirectEmission(w0);
  takeDirectEmission(w1);
  ComponentMotions motions;
  std::vector<std::string> layers = decompositionComponents(in.k0);
  layers.emplace_back();
  for (const std::string& layer : layers) {
    const std::string prefix = layer.empty() ? "" : layer + ".";
    motions.components[layer] = ComponentMotion(motionTowards(w0, NeighbourFrame::Next, prefix, "k0"),
                                                motionTowards(w1, NeighbourFrame::Previous, prefix, "k1"));
  }
  motions.components[in.flowing].irradianceForward = in.field;
  motions.components[in.flowing].irradianceBackward = in.field;
  motions.components[in.flowing].hasIrradianceMotion = true;
  InterpolationSettings settings;
  settings.unknownChangeMasks = false;  // as the task
  LayeredKeyframes keys = wholeKeyframes(w0, w1, motions);
  if (ownReflectance) keys.inBetween = &in.features;
  InterpolationResult whole = interpolateFrameDetailed(keys, 1.0f / 3.0f, settings);
  addDirectEmission(whole.frame, directEmissionOf(in.features));
  return whole;
}

// The task reads its keyframes a component at a time, each decoded alone from its file when
// the worker keeps no decoded frames: its frame is the same bits as interpolating the whole
// keyframes with every component's motion at once, modulated by the frame's own
// reflectance (its features have the keyframes' samples).
TEST(InterpolateTask, KeyframesReadAComponentAtATimeGiveTheWholeFramesInterpolation) {
  const InterpolationFiles in("pathfarm_interpolate_parts", -0.5f);
  const TaskOutput outputs[2] = {in.run(in.lease, 0), in.run(in.lease, TaskRunner::kDefaultDecodedInputBytes)};
  const FrameImage alone = decodeExr(outputBytes(outputs[0]), "alone");
  const FrameImage fromWhole = decodeExr(outputBytes(outputs[1]), "from whole");
  const InterpolationResult whole = wholeInterpolation(in, true);
  const FrameImage expected = asIntermediateChunk(whole.frame);
  // The interpolation's own re-render causes (the task adds its checks' as other causes).
  for (const TaskOutput& output : outputs) {
    EXPECT_EQ(output.metrics.at("rerender_holes"), static_cast<double>(whole.holePixels));
    EXPECT_EQ(output.metrics.at("rerender_silhouettes"), static_cast<double>(whole.silhouettePixels));
    EXPECT_EQ(output.metrics.at("rerender_untracked"), static_cast<double>(whole.untrackedPixels));
    EXPECT_EQ(output.metrics.at("rerender_illumination"), static_cast<double>(whole.illuminationPixels));
  }
  EXPECT_GT(whole.untrackedPixels, 0u);
  // rerender_causes.Y holds each cause's pixels as a bit, in the report's order of causes.
  const std::vector<float>& causeBits = alone.channel("rerender_causes.Y");
  const char* causes[] = {"holes",    "silhouettes", "untracked",      "illumination",
                          "mismatch", "light_edges", "light_mismatch", "moving_caustics"};
  for (int c = 0; c < 8; ++c) {
    double withBit = 0;
    for (const float bits : causeBits) withBit += (static_cast<int>(bits) >> c) & 1;
    EXPECT_EQ(withBit, outputs[0].metrics.at(std::string("rerender_") + causes[c])) << causes[c];
  }
  const std::vector<float>& flagged = alone.channel("rerender.Y");
  for (size_t p = 0; p < flagged.size(); ++p) ASSERT_EQ(flagged[p] > 0.5f, causeBits[p] > 0.0f) << "pixel " << p;

  for (const FrameImage* result : {&alone, &fromWhole})
    for (const std::string& name : expected.channelNames()) {
      if (name == "rerender.Y") continue;  // the task adds its checks' pixels
      ASSERT_TRUE(result->hasChannel(name)) << name;
      EXPECT_TRUE(result->channel(name) == expected.channel(name)) << name;
    }
  for (const std::string& name : {std::string("R"), in.flowing + ".color.G"})
    EXPECT_NE(expected.channel(name), in.features.channel(name)) << "not interpolated: " << name;
  EXPECT_NE(expected.channel("G"), wholeInterpolation(in, false).frame.channel("G"))
      << "the features' reflectance changes nothing here";
}

// Features with fewer samples than the keyframes leave the keyframes' reflectance: their
// noise would cost more than the texture edges gain.
// The task's frame is `computed`'s as its chunk stores it, channel by channel (its re-render
// mask aside).
void expectSameFrame(const FrameImage& result, const FrameImage& computed) {
  const FrameImage expected = asIntermediateChunk(computed);
  for (const std::string& name : expected.channelNames())
    if (name != "rerender.Y") EXPECT_TRUE(result.channel(name) == expected.channel(name)) << name;
}

TEST(InterpolateTask, FeaturesWithFewerSamplesThanTheKeyframesLeaveTheKeyframesReflectance) {
  const InterpolationFiles in("pathfarm_interpolate_few_features", -0.5f, kWidth, kHeight, 4);
  const FrameImage result = decodeExr(outputBytes(in.run(in.lease, 0)), "interpolated");
  const FrameImage splatted = wholeInterpolation(in, false).frame, own = wholeInterpolation(in, true).frame;
  EXPECT_NE(splatted.channel("G"), own.channel("G")) << "the features' reflectance changes nothing here";
  expectSameFrame(result, splatted);
}

// 4-spp features whose reflectance took the keyframes' 8 samples (the planner's feature
// render): their reflectance is used.
TEST(InterpolateTask, FeaturesWhoseReflectanceHasTheKeyframesSamplesModulateTheInterpolation) {
  const InterpolationFiles in("pathfarm_interpolate_reflectance_samples", -0.5f, kWidth, kHeight, 4, 8);
  const FrameImage result = decodeExr(outputBytes(in.run(in.lease, 0)), "interpolated");
  const FrameImage splatted = wholeInterpolation(in, false).frame, own = wholeInterpolation(in, true).frame;
  EXPECT_NE(splatted.channel("G"), own.channel("G")) << "the features' reflectance changes nothing here";
  expectSameFrame(result, own);
}

// Keyframes of more samples than kMaxOwnReflectanceSpp, features whose reflectance took
// that many (the planner's di feature render at 64 spp): their reflectance is used; one
// sample fewer, it is not.
TEST(InterpolateTask, FeaturesReflectanceNeedsNoMoreThanTheCappedSamples) {
  const int keyframeSpp = kMaxOwnReflectanceSpp * 2;
  const InterpolationFiles capped("pathfarm_interpolate_capped_reflectance", -0.5f, 48, 27, 4, kMaxOwnReflectanceSpp,
                                  keyframeSpp);
  expectSameFrame(decodeExr(outputBytes(capped.run(capped.lease, 0)), "interpolated"),
                  wholeInterpolation(capped, true).frame);
  const InterpolationFiles fewer("pathfarm_interpolate_fewer_reflectance", -0.5f, 48, 27, 4,
                                 kMaxOwnReflectanceSpp - 1, keyframeSpp);
  const FrameImage splatted = wholeInterpolation(fewer, false).frame;
  EXPECT_NE(splatted.channel("G"), wholeInterpolation(fewer, true).frame.channel("G"))
      << "the features' reflectance changes nothing here";
  expectSameFrame(decodeExr(outputBytes(fewer.run(fewer.lease, 0)), "interpolated"), splatted);
}

// An in-between frame interpolated window by window (each task reading the keyframe rows
// whose content its motion can bring into its rows, and the feature rows its checks reach)
// and joined is the same bytes, the same re-render and the same counts as the frame
// interpolated by one task. One component's light moves 15 rows from the first keyframe
// and 30 from the second, farther than the checks' reach, across every window border.
TEST(InterpolateTask, WindowsInterpolatedApartAndJoinedAreTheWholeFramesBytes) {
  constexpr int kTall = 160, kFlowRows = 45;
  InterpolationFiles in("pathfarm_interpolate_windows", static_cast<float>(kFlowRows), 48, kTall);
  in.lease.mutable_spec()->set_filter_window_rows(40);
  const TaskOutput one = in.run(in.lease, 0);
  const std::string expected = outputBytes(one);
  const std::vector<RowWindow> windows = filterWindowsOf(in.lease.spec());
  ASSERT_EQ(windows.size(), 4u);
  Lease join = interpolateLease();
  *join.mutable_spec() = in.lease.spec();
  std::map<std::string, double> summed;
  for (const RowWindow& rows : windows) {
    Lease part = in.lease;
    PixelWindow& w = *part.mutable_params()->mutable_window();
    w.set_x1(48);
    w.set_y0(rows.first);
    w.set_y1(rows.end);
    const TaskOutput output = in.run(part, rows.first % 80 == 0 ? 0 : TaskRunner::kDefaultDecodedInputBytes);
    EXPECT_TRUE(output.followUps.empty()) << "a window's re-render goes with the join's";
    // Its rows, the checks' 9 around them, the largest displacement (30 rows), the whole
    // flow its sources' depths are read across (45 rows) and 2.
    EXPECT_EQ(output.metrics.at("keyframe_rows_read"),
              std::min(kTall, rows.end + 9 + 77) - std::max(0, rows.first - 9 - 77));
    for (const auto& [name, value] : output.metrics) summed[name] += value;
    const std::string name = "window" + std::to_string(rows.first);
    in.files[name] = in.folder / (name + ".exr");
    std::ofstream(in.files[name], std::ios::binary) << outputBytes(output);
    InterpolationFiles::addInput(join, name, TASK_INTERPOLATE, kFrame, "");
    *join.mutable_input_params(join.input_params_size() - 1)->mutable_window() = w;
  }
  const TaskOutput joined = in.run(join, 0);
  EXPECT_TRUE(outputBytes(joined) == expected) << "the joined windows differ from the whole frame's interpolation";
  ASSERT_EQ(joined.followUps.size(), one.followUps.size());
  ASSERT_GT(one.followUps.size(), 0u);
  for (size_t t = 0; t < one.followUps.size(); ++t)
    EXPECT_EQ(joined.followUps[t].SerializeAsString(), one.followUps[t].SerializeAsString()) << "re-render tile " << t;
  EXPECT_EQ(joined.metrics.at("rerender_pixels"), one.metrics.at("rerender_pixels"));
  for (const char* cause : {"rerender_holes", "rerender_silhouettes", "rerender_untracked", "rerender_illumination",
                            "rerender_mismatch", "rerender_light_edges", "rerender_light_mismatch",
                            "rerender_moving_caustics"})
    EXPECT_EQ(summed.at(cause), one.metrics.at(cause)) << cause;
}

}  // namespace
}  // namespace pathfarm::farm
