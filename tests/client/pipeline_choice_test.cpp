#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>

#include "renderer/integrators/frame_renderer.h"
#include "client/pipeline_choice.h"
#include "scheduler/planner.h"

namespace pathfarm::farm {
namespace {

ShotSpec probedShot(int64_t frames, int width, int height) {
  ShotSpec spec;
  spec.set_name("shot");
  spec.set_frame_start(100);
  spec.set_frame_end(100 + frames - 1);
  spec.set_width(width);
  spec.set_height(height);
  spec.set_spp(64);
  spec.set_tile(64);
  return spec;
}

ShotSpec candidateSpec(const std::string& pipeline, int keyframeInterval = 1) {
  ShotSpec spec = probedShot(24, 320, 180);
  spec.set_pipeline(*pipelineNamed(pipeline));
  spec.set_reference_spp(1024);
  spec.add_evaluation_frames(111);
  if (isFilteringPipeline(spec.pipeline())) {
    spec.set_decompose("diffuse=ED,residual");
    spec.set_keyframe_interval(keyframeInterval);
    spec.set_feature_spp(4);
  }
  if (pipeline == "tgpt") {
    spec.set_poisson_window(10);
    spec.set_poisson_overlap(5);
    spec.set_poisson_norm("l1");
  }
  return spec;
}

CandidateMeasure measured(const std::string& pipeline, double coreSecondsPerFrame, double relMse,
                          double standardError = 0) {
  CandidateMeasure m;
  m.pipeline = *pipelineNamed(pipeline);
  m.coreSecondsPerFrame = coreSecondsPerFrame;
  m.probeCoreSeconds = coreSecondsPerFrame;
  m.relMse = relMse;
  m.relMseStandardError = standardError;
  return m;
}

// Each crop's size, and the camera's zoom exactly the ratio of the heights.
void expectCrops(const ProbeGeometry& g, int scale, int width, int height, int shotHeight) {
  EXPECT_EQ(g.scale, scale);
  EXPECT_EQ(g.width, width);
  EXPECT_EQ(g.height, height);
  EXPECT_DOUBLE_EQ(g.zoom, static_cast<double>(shotHeight) / height);
}

TEST(PipelineChoice, TheProbeCoversTheLongestIntervalInTheMiddleOfTheShot) {
  const ProbeGeometry g = probeGeometry(probedShot(24, 320, 180), 8);
  EXPECT_EQ(g.frames(), 9);
  EXPECT_EQ(g.frameStart, 100 + (24 - 9) / 2);
  EXPECT_EQ(probeGeometry(probedShot(24, 320, 180), 2).frames(), 5);  // never fewer than 5
  ShotSpec manySamples = probedShot(24, 320, 180);
  manySamples.set_spp(256);
  EXPECT_EQ(probeGeometry(manySamples, 2).frames(), 4);  // or 4 from 256 spp
  EXPECT_EQ(probeGeometry(probedShot(3, 320, 180), 8).frames(), 3);   // nor more than the shot
}

TEST(PipelineChoice, ErrorsAreMeasuredOnFramesWithNeighboursOnBothSidesAsTheShotsFramesHave) {
  const ProbeGeometry middle = probeGeometry(probedShot(24, 320, 180), 4);  // frames 109..113
  EXPECT_EQ(middle.measuredStart, middle.frameStart + 1);
  EXPECT_EQ(middle.measuredEnd, middle.frameEnd - 1);
  EXPECT_EQ(middle.measuredFrames(), 3);
  // A longer interval lengthens the probe around the same number of measured frames, in
  // its middle: 3, and from 256 spp 2.
  const ProbeGeometry longer = probeGeometry(probedShot(24, 320, 180), 8);  // frames 107..115
  EXPECT_EQ(longer.measuredStart, 110);
  EXPECT_EQ(longer.measuredEnd, 112);
  ShotSpec manySamples = probedShot(24, 320, 180);
  manySamples.set_spp(256);
  const ProbeGeometry longerAtHighSpp = probeGeometry(manySamples, 5);  // frames 109..114
  EXPECT_EQ(longerAtHighSpp.measuredStart, 111);
  EXPECT_EQ(longerAtHighSpp.measuredEnd, 112);
  // A probe that reaches an end of the shot measures every frame: the shot's own first or
  // last frame lacks the neighbour too.
  for (const int64_t frames : {3, 5, 6}) {
    const ProbeGeometry whole = probeGeometry(probedShot(frames, 320, 180), 1);
    EXPECT_EQ(whole.measuredStart, whole.frameStart) << frames;
    EXPECT_EQ(whole.measuredEnd, whole.frameEnd) << frames;
  }
}

TEST(PipelineChoice, TheProbeIsSmallerTheShorterTheShotAndAlwaysEven) {
  // A short shot: the probe is its centre quarter per axis, rounded up to even, and the
  // camera zooms in by exactly the ratio of the heights.
  const ProbeGeometry short_ = probeGeometry(probedShot(24, 321, 181), 4);
  expectCrops(short_, 4, 80, 46, 181);
  // A long one: the same frames are a small share of it, so the probe renders them larger.
  const ProbeGeometry long_ = probeGeometry(probedShot(2400, 1920, 1080), 4);
  EXPECT_LT(long_.scale, short_.scale);
  EXPECT_EQ(long_.width % 2, 0);
  EXPECT_EQ(long_.height % 2, 0);
  // No edge of the crop is under 32 pixels, unless the shot's is: then it is the whole frame.
  const ProbeGeometry small = probeGeometry(probedShot(24, 128, 72), 4);
  EXPECT_EQ(small.scale, 2);
  EXPECT_EQ(small.height, 36);
  const ProbeGeometry tiny = probeGeometry(probedShot(24, 40, 12), 4);
  EXPECT_EQ(tiny.width, 40);
  EXPECT_EQ(tiny.height, 12);
  EXPECT_DOUBLE_EQ(tiny.zoom, 1.0);
  // These are one crop each, at the centre: a grid's crops of 32 rows would hold far
  // more pixels than one.
  for (const ProbeGeometry& g : {short_, small, tiny}) {
    ASSERT_EQ(g.windows.size(), 1u);
    EXPECT_EQ(g.windows[0].shiftX, 0.0);
    EXPECT_EQ(g.windows[0].shiftY, 0.0);
  }
}

TEST(PipelineChoice, ALargerShotIsProbedInAGridOfCropsOverTheWholePicture) {
  // 640x360 for 24 frames: one crop would be a quarter per axis (160x90). Nine of a twelfth
  // would be 30 rows; at the floor of 32 rows (58x32, the shot's aspect) they hold 1.16
  // times its pixels, and see the whole picture, not only its centre.
  const ProbeGeometry g = probeGeometry(probedShot(24, 640, 360), 4);
  expectCrops(g, 4, 58, 32, 360);
  EXPECT_DOUBLE_EQ(g.pixels(), 9.0 * 58 * 32);
  ASSERT_EQ(g.windows.size(), 9u);
  std::set<std::pair<double, double>> centres;
  for (const ProbeWindow& w : g.windows) {
    // Centred on the ninths of the picture: 0 or a third from its centre, each way.
    for (const double shift : {w.shiftX, w.shiftY})
      EXPECT_TRUE(std::abs(shift) < 1e-12 || std::abs(std::abs(shift) - 1.0 / 3) < 1e-12) << shift;
    // Inside the picture: a third out, with half of a crop's width beyond, is within half of it.
    EXPECT_LE(std::abs(w.shiftX) * 640 + 58 / 2.0, 320.0);
    EXPECT_LE(std::abs(w.shiftY) * 360 + 32 / 2.0, 180.0);
    centres.insert({w.shiftX, w.shiftY});
  }
  EXPECT_EQ(centres.size(), 9u) << "no crop twice";
  // A 1080p shot's grid needs no floor: 160x90 crops, nine of them the pixels of one 480x270.
  const ProbeGeometry hd = probeGeometry(probedShot(24, 1920, 1080), 4);
  EXPECT_EQ(hd.width, 160);
  EXPECT_EQ(hd.height, 90);
  EXPECT_EQ(hd.windows.size(), 9u);
  // Every candidate probes every crop, into a folder of its own, under a name of its own.
  std::set<std::string> names, outputs;
  for (size_t window = 0; window < g.windows.size(); ++window) {
    const ShotSpec probe = probeSpecOf(candidateSpec("d", 1), g, window, "/tmp/probes");
    EXPECT_EQ(probe.camera_shift_x(), g.windows[window].shiftX);
    EXPECT_EQ(probe.camera_shift_y(), g.windows[window].shiftY);
    EXPECT_EQ(probe.output(), probeOutput("/tmp/probes", PIPELINE_D, g, window).string());
    EXPECT_EQ(probe.output(), "/tmp/probes/d/window_" + std::to_string(window));
    EXPECT_NO_THROW(planShot(probe));
    names.insert(probe.name());
    outputs.insert(probe.output());
  }
  EXPECT_EQ(names.size(), 9u);
  EXPECT_EQ(outputs.size(), 9u);
}

TEST(PipelineChoice, EveryProbePlansAndOnlyPlainPtSamplesApart) {
  const ProbeGeometry g = probeGeometry(probedShot(24, 320, 180), 6);  // frames 108..114, measured 110..112
  for (const auto& [pipeline, k] : std::vector<std::pair<std::string, int>>{{"pt", 1}, {"d", 1}, {"di", 6},
                                                                            {"dui", 6}, {"tgpt", 1}}) {
    const ShotSpec probe = probeSpecOf(candidateSpec(pipeline, k), g, 0, "/tmp/probes");
    EXPECT_EQ(pipelineName(probe.pipeline()), pipeline);
    EXPECT_EQ(probe.output(), "/tmp/probes/" + pipeline);
    EXPECT_EQ(probe.width(), g.width);
    // The stand-in renders only the frames errors are measured on, the interpolating
    // candidates the whole probe, the others the measured frames and their neighbours.
    const bool interpolates = k > 1;
    EXPECT_EQ(probe.frame_start(), pipeline == "pt" ? g.measuredStart : interpolates ? g.frameStart : g.measuredStart - 1)
        << pipeline;
    EXPECT_EQ(probe.frame_end(), pipeline == "pt" ? g.measuredEnd : interpolates ? g.frameEnd : g.measuredEnd + 1)
        << pipeline;
    EXPECT_EQ(g.frameCountOf(candidateSpec(pipeline, k)), probe.frame_end() - probe.frame_start() + 1) << pipeline;
    EXPECT_EQ(probe.reference_spp(), 0) << "a probe measures nothing itself";
    EXPECT_TRUE(probe.evaluation_frames().empty());
    EXPECT_EQ(probe.first_sample(), pipeline == "pt" ? kIndependentFirstSample : 0u) << pipeline;
    // The stand-in renders more samples than the shot, tgpt (the costliest) fewer.
    const int spp = pipeline == "pt" ? standInSpp(64) : pipeline == "tgpt" ? 64 / kGradientProbeSppDivisor : 64;
    EXPECT_EQ(probe.spp(), spp) << pipeline;
    EXPECT_DOUBLE_EQ(probeSppRatio(candidateSpec(pipeline, k)), spp / 64.0) << pipeline;
    EXPECT_DOUBLE_EQ(probe.camera_zoom(), 180.0 / g.height);
    EXPECT_NO_THROW(planShot(probe)) << pipeline;
    if (pipeline == "tgpt") {
      EXPECT_LE(probe.poisson_window(), probe.frame_end() - probe.frame_start() + 1);
    }
  }
}

TEST(PipelineChoice, TheStandInRendersTwiceTheSppAndAtLowSppUpToFourTimesTowards256) {
  for (const auto& [shotSpp, standIn] : std::vector<std::pair<int, int>>{
           {16, 64}, {64, 256}, {100, 256}, {128, 256}, {256, 512}, {1000, 2000}})
    EXPECT_EQ(standInSpp(shotSpp), standIn) << shotSpp;
  ShotSpec pt = candidateSpec("pt");
  pt.set_spp(100);
  EXPECT_EQ(probeSpecOf(pt, probeGeometry(probedShot(24, 320, 180), 1), 0, "/tmp/probes").spp(), 256);
  EXPECT_DOUBLE_EQ(probeSppRatio(pt), 2.56);
}

TEST(PipelineChoice, TgptsProbeRendersFewerSamplesOnlyWhereSamplesOutweighATasksFixedCosts) {
  ShotSpec tgpt = candidateSpec("tgpt", 1);
  for (const auto& [shotSpp, probeSpp] : std::vector<std::pair<int, int>>{{256, 64}, {64, 16}, {63, 63}, {4, 4}}) {
    tgpt.set_spp(shotSpp);
    EXPECT_EQ(probeSpecOf(tgpt, probeGeometry(probedShot(24, 320, 180), 4), 0, "/tmp/probes").spp(), probeSpp);
    EXPECT_DOUBLE_EQ(probeSppRatio(tgpt), static_cast<double>(probeSpp) / shotSpp);
  }
}

TEST(PipelineChoice, ASecondRoundProbeRendersTheShotsSppUnderItsOwnNameAndFolder) {
  const ShotSpec tgpt = candidateSpec("tgpt", 1);
  const ProbeGeometry g = probeGeometry(probedShot(24, 320, 180), 4);
  const ShotSpec first = probeSpecOf(tgpt, g, 0, "/tmp/probes");
  const ShotSpec again = probeSpecOf(tgpt, g, 0, "/tmp/probes", ProbeRound::AtShotSpp);
  EXPECT_EQ(first.spp(), 64 / kGradientProbeSppDivisor);
  EXPECT_EQ(again.spp(), 64);
  EXPECT_DOUBLE_EQ(probeSppRatio(tgpt, ProbeRound::AtShotSpp), 1);
  EXPECT_EQ(again.output(), "/tmp/probes/tgpt_at_shot_spp");
  EXPECT_EQ(again.output(), probeOutput("/tmp/probes", PIPELINE_TGPT, g, 0, ProbeRound::AtShotSpp).string());
  // A name of its own, so that a keyed resubmission cannot mistake it for the first round's.
  EXPECT_NE(again.name(), first.name());
  EXPECT_EQ(again.frame_start(), first.frame_start());
  EXPECT_EQ(again.frame_end(), first.frame_end());
  EXPECT_NO_THROW(planShot(again));
}

// tgpt's first probe renders a quarter of the samples (sppRatio 0.25); the callback stands
// in for its second probe at the shot's spp.
CandidateMeasure atQuarterSpp(CandidateMeasure m) {
  m.sppRatio = 0.25;
  return m;
}

TEST(PipelineChoice, AWinnerProbedAtFewerSamplesIsProbedAgainAtTheShotsAndMayLose) {
  const ShotSpec shot = probedShot(24, 320, 180);
  const ProbeGeometry g = probeGeometry(shot, 4);
  // pt 10 at 0.01; d 11 at 0.002: 0.22 of pt; tgpt at a quarter of the spp 60 at 0.0002:
  // 0.12, the winner. At the shot's spp its error reads 5 times higher: 0.6, and d wins.
  std::vector<Pipeline> probedAgain;
  const PipelineChoice choice = choosePipelineFromProbes(
      {measured("pt", 10, 0.01), measured("d", 11, 0.002), atQuarterSpp(measured("tgpt", 60, 0.0002))}, g, shot,
      [&](Pipeline pipeline) {
        probedAgain.push_back(pipeline);
        return measured("tgpt", 60, 0.001);
      });
  EXPECT_EQ(probedAgain, std::vector<Pipeline>{PIPELINE_TGPT});
  EXPECT_EQ(pipelineName(choice.pipeline), "d");
  EXPECT_DOUBLE_EQ(choice.costAtEqualError, 1.1 * 0.2);
  EXPECT_DOUBLE_EQ(choice.probeCoreSeconds, 10 + 11 + 60 + 60) << "both of tgpt's probes count";
  EXPECT_NE(choice.reason.find("tgpt 0.60"), std::string::npos) << choice.reason;
  EXPECT_NE(choice.reason.find("tgpt won at 16 spp (0.12) and was probed again at the shot's 64"), std::string::npos)
      << choice.reason;
}

TEST(PipelineChoice, AWinnerConfirmedAtTheShotsSppIsChosenWithTheSecondMeasure) {
  const ShotSpec shot = probedShot(24, 320, 180);
  const ProbeGeometry g = probeGeometry(shot, 4);
  const PipelineChoice choice = choosePipelineFromProbes(
      {measured("pt", 10, 0.01), measured("d", 11, 0.002), atQuarterSpp(measured("tgpt", 60, 0.0002))}, g, shot,
      [](Pipeline) { return measured("tgpt", 64, 0.00025); });
  EXPECT_EQ(pipelineName(choice.pipeline), "tgpt");
  EXPECT_DOUBLE_EQ(choice.predictedRelMse, 0.00025);
  EXPECT_DOUBLE_EQ(choice.costAtEqualError, 6.4 * 0.025);
}

TEST(PipelineChoice, ALoserAtFewerSamplesIsNotProbedAgainNorIsAFailedSecondProbeChosen) {
  const ShotSpec shot = probedShot(24, 320, 180);
  const ProbeGeometry g = probeGeometry(shot, 4);
  // Read low, as a quarter of the samples reads it, tgpt still loses: no second probe.
  const auto never = [](Pipeline) -> CandidateMeasure {
    ADD_FAILURE() << "a loser was probed again";
    return {};
  };
  EXPECT_EQ(choosePipelineFromProbes({measured("pt", 10, 0.01), measured("d", 11, 0.002),
                                      atQuarterSpp(measured("tgpt", 60, 0.0005))},
                                     g, shot, never)
                .pipeline,
            PIPELINE_D);  // tgpt 0.30 against d's 0.22
  // A second probe that fails leaves tgpt out, as a failed first one would.
  const PipelineChoice choice = choosePipelineFromProbes(
      {measured("pt", 10, 0.01), measured("d", 11, 0.002), atQuarterSpp(measured("tgpt", 60, 0.0002))}, g, shot,
      [](Pipeline) {
        CandidateMeasure failed = measured("tgpt", 0, 0);
        failed.failure = "shot 9 SHOT_CANCELLED";
        return failed;
      });
  EXPECT_EQ(pipelineName(choice.pipeline), "d");
  EXPECT_NE(choice.reason.find("tgpt failed (shot 9 SHOT_CANCELLED)"), std::string::npos) << choice.reason;
}

TEST(PipelineChoice, TheLowestCostAtEqualErrorWins) {
  const ShotSpec shot = probedShot(24, 320, 180);
  const ProbeGeometry g = probeGeometry(shot, 4);
  // pt: 10 core-seconds at relMSE 0.01. d: 11 at 0.002, 0.22 of pt at equal error. dui:
  // 4 at 0.004, 0.16. tgpt: 60 at 0.001, 0.6.
  const PipelineChoice choice = decidePipeline(
      {measured("pt", 10, 0.01), measured("d", 11, 0.002), measured("dui", 4, 0.004), measured("tgpt", 60, 0.001)}, g, shot);
  EXPECT_EQ(pipelineName(choice.pipeline), "dui");
  EXPECT_DOUBLE_EQ(choice.predictedRelMse, 0.004);
  const double pixelRatio = 320.0 * 180 / (g.width * g.height);
  EXPECT_NEAR(choice.predictedCoreSecondsPerFrame, 4.0 * pixelRatio, 1e-9);
  EXPECT_DOUBLE_EQ(choice.probeCoreSeconds, 85);
  EXPECT_NE(choice.reason.find("dui 0.16"), std::string::npos) << choice.reason;
  EXPECT_NE(choice.reason.find("tgpt 0.60"), std::string::npos) << choice.reason;
}

TEST(PipelineChoice, PlainPtWinsWhenNothingBeatsIt) {
  const ShotSpec shot = probedShot(24, 320, 180);
  const PipelineChoice choice =
      decidePipeline({measured("pt", 10, 0.01), measured("d", 11, 0.0095), measured("tgpt", 60, 0.002)}, probeGeometry(shot, 1), shot);
  EXPECT_EQ(pipelineName(choice.pipeline), "pt");
}

TEST(PipelineChoice, AnErrorWithinTheProbesNoiseCannotWinByItself) {
  // An estimate within two standard errors of zero (here below it) counts as two standard
  // errors, so a cheaper pipeline with a real error still beats a costlier one that
  // measured nothing.
  const ShotSpec shot = probedShot(24, 320, 180);
  const PipelineChoice choice = decidePipeline(
      {measured("pt", 10, 0.01), measured("tgpt", 60, -0.001, 0.0005), measured("dui", 2, 0.002, 0.0005)},
      probeGeometry(shot, 4), shot);
  EXPECT_EQ(pipelineName(choice.pipeline), "dui");  // 0.2 x 0.2 = 0.04 against 6 x 0.1 = 0.6
  EXPECT_NE(choice.reason.find("tgpt 0.60 (its error within the probe's noise)"), std::string::npos) << choice.reason;
  // Resolved estimates are taken as they are: the same tgpt with a smaller error bar wins.
  EXPECT_EQ(decidePipeline({measured("pt", 10, 0.01), measured("tgpt", 60, 0.00005, 0.00001),
                            measured("dui", 2, 0.002, 0.0005)},
                           probeGeometry(shot, 4), shot)
                .pipeline,
            PIPELINE_TGPT);  // 6 x 0.005 = 0.03
  // When plain pt has no error at all, a pipeline with any error cannot beat it.
  EXPECT_EQ(decidePipeline({measured("pt", 10, 0.0), measured("dui", 2, 1e-4)}, probeGeometry(shot, 4), shot).pipeline,
            PIPELINE_PT);
}

TEST(PipelineChoice, AFailedProbeIsLeftOutAndNamed) {
  const ShotSpec shot = probedShot(24, 320, 180);
  CandidateMeasure failed = measured("dui", 0, 0);
  failed.failure = "shot 3 SHOT_FAILED: out of memory";
  const PipelineChoice choice =
      decidePipeline({measured("pt", 10, 0.01), failed, measured("d", 11, 0.002)}, probeGeometry(shot, 4), shot);
  EXPECT_EQ(pipelineName(choice.pipeline), "d");
  EXPECT_NE(choice.reason.find("dui failed (shot 3 SHOT_FAILED: out of memory)"), std::string::npos);
  EXPECT_THROW(decidePipeline({measured("d", 11, 0.002)}, probeGeometry(shot, 4), shot), std::invalid_argument);
  CandidateMeasure ptFailed = measured("pt", 10, 0.01);
  ptFailed.failure = "cancelled";
  EXPECT_THROW(decidePipeline({ptFailed, measured("d", 11, 0.002)}, probeGeometry(shot, 4), shot), std::invalid_argument);
}

}  // namespace
}  // namespace pathfarm::farm
