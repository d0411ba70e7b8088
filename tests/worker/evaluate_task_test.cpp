// From the evaluation frames to the verdict a user reads: the evaluate task measures a
// shot's final frames and plain pt's against a noisy reference, and the report claims
// that the pipeline paid off only where the interval of its cost at equal error lies
// below 1. The frames are pictures with a known truth and known noise.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "scheduler/shot_report.h"
#include "scheduler/task_records.h"
#include "test_support.h"
#include "worker/failure_class.h"
#include "worker/filter_tasks.h"

namespace pathfarm::farm {
namespace {

constexpr int kEvaluatedSize = 48;
constexpr double kPtSigma = 0.05;

TaskInput evaluationInput(TaskKind kind, TaskRole role, int64_t frame, FrameImage image) {
  TaskInput input{kind, {}, std::make_shared<FrameImage>(std::move(image))};
  input.params.set_frame(frame);
  input.params.set_role(role);
  return input;
}

// The evaluation's inputs on frames 1 and 2: a reference of 1024 samples, final frames
// with `errorOverPt` times pt's expected squared error, and `baselineRenders` independent
// renders of pt per frame (each input's noise drawn from `seed`).
std::vector<TaskInput> evaluationInputs(double errorOverPt, int baselineRenders, uint64_t seed) {
  const FrameImage truth = test_support::smoothTruth(kEvaluatedSize, kEvaluatedSize);
  std::vector<TaskInput> inputs;
  for (int64_t frame = 1; frame <= 2; ++frame) {
    const uint64_t base = 8 * seed + 4 * static_cast<uint64_t>(frame);
    inputs.push_back(evaluationInput(TASK_ASSEMBLE_FRAME, ROLE_REFERENCE, frame,
                                     test_support::noisyCopy(truth, 0.4 / 32, base, true)));
    inputs.push_back(
        evaluationInput(TASK_COMPOSITE, ROLE_UNSPECIFIED, frame,
                        test_support::noisyCopy(truth, kPtSigma * std::sqrt(errorOverPt), base + 2, false)));
    for (int repeat = baselineRenders - 1; repeat >= 0; --repeat) {  // in any order
      const uint64_t noise = base + 1 + (static_cast<uint64_t>(repeat) << 32);
      TaskInput baseline = evaluationInput(TASK_ASSEMBLE_FRAME, ROLE_BASELINE, frame,
                                           test_support::noisyCopy(truth, kPtSigma, noise, true));
      baseline.params.set_baseline_repeat(repeat);
      inputs.push_back(std::move(baseline));
    }
  }
  return inputs;
}

// The verdict on a dui shot that costs what plain pt costs per frame and whose final
// frames have `errorOverPt` times pt's expected squared error (evaluationInputs).
std::string verdictAt(double errorOverPt, uint64_t seed) {
  std::vector<TaskInput> inputs = evaluationInputs(errorOverPt, 1, seed);
  ShotSpec spec;
  spec.set_pipeline(PIPELINE_DUI);
  spec.set_frame_start(0);
  spec.set_frame_end(3);
  spec.set_width(kEvaluatedSize);
  spec.set_height(kEvaluatedSize);
  spec.set_spp(64);
  spec.set_keyframe_interval(3);
  std::vector<TaskRecord> tasks = {taskRecord(TASK_RENDER_TILE, ROLE_KEYFRAME, 0, 8.0),  // 2 core-seconds a frame
                                   taskRecord(TASK_RENDER_TILE, ROLE_BASELINE, 1, 1.5),  // pt: 2 a frame
                                   taskRecord(TASK_ASSEMBLE_FRAME, ROLE_BASELINE, 1, 0.5),
                                   taskRecord(TASK_EVALUATE, ROLE_UNSPECIFIED, 0, 0.1)};
  tasks.back().metrics = runEvaluateTask(Lease(), inputs).metrics;
  const ShotReport report = buildReport(ShotSummary(), spec, tasks);
  EXPECT_DOUBLE_EQ(report.relative_cost(), 1.0);
  return report.verdict();
}

TEST(EvaluateTask, APipelineTenPercentWorseThanPtIsNeverSaidToPayOff) {
  int said = 0;
  for (uint64_t seed = 0; seed < 100; ++seed) {
    const std::string verdict = verdictAt(1.1, seed);
    EXPECT_EQ(verdict.find("paid off:"), std::string::npos) << verdict;
    if (verdict.rfind("dui did not pay off", 0) == 0) ++said;
  }
  // Not by saying nothing: with 1024 reference samples the loss is usually resolved.
  EXPECT_GE(said, 50);
}

TEST(EvaluateTask, APipelineAThirdBetterThanPtIsSaidToPayOff) {
  int said = 0;
  for (uint64_t seed = 0; seed < 20; ++seed)
    if (verdictAt(0.67, seed).rfind("dui paid off", 0) == 0) ++said;
  EXPECT_GE(said, 18);
}

TEST(EvaluateTask, IndependentBaselineRendersNarrowTheErrorRatioWhichStillCoversTheTruth) {
  constexpr int kTrials = 40;
  int covered = 0;
  std::vector<double> narrowing;
  const auto width = [](const std::map<std::string, double>& figures) {
    return figures.at("error_ratio_high") - figures.at("error_ratio_low");
  };
  for (uint64_t seed = 0; seed < kTrials; ++seed) {
    std::vector<TaskInput> oneRender = evaluationInputs(0.5, 1, seed), fourRenders = evaluationInputs(0.5, 4, seed);
    const auto one = runEvaluateTask(Lease(), oneRender).metrics, four = runEvaluateTask(Lease(), fourRenders).metrics;
    if (four.at("error_ratio_low") <= 0.5 && 0.5 <= four.at("error_ratio_high")) ++covered;
    narrowing.push_back(width(four) / width(one));
  }
  EXPECT_GE(covered, kTrials * 9 / 10);
  // The ratio's spread is the final frames' noise and pt's, alike here: four pt renders
  // leave sqrt(1 + 1/4) of sqrt(2), 0.79 of the width. (Pt's own interval narrows less:
  // the blocks' errors differ by the picture's brightness as much as by noise.)
  std::sort(narrowing.begin(), narrowing.end());
  const double median = narrowing[narrowing.size() / 2];
  EXPECT_GT(median, 0.7);
  EXPECT_LT(median, 0.88);
}

TEST(EvaluateTask, AFrameMissingOneOfItsBaselineRendersIsRefused) {
  std::vector<TaskInput> inputs = evaluationInputs(0.5, 2, 0);
  const auto lastOfFrameTwo = std::find_if(inputs.begin(), inputs.end(), [](const TaskInput& input) {
    return input.params.role() == ROLE_BASELINE && input.params.frame() == 2 && input.params.baseline_repeat() == 1;
  });
  ASSERT_NE(lastOfFrameTwo, inputs.end());
  inputs.erase(lastOfFrameTwo);
  EXPECT_THROW(runEvaluateTask(Lease(), inputs), BadInput);
}

// The contact sheet travels inside the report, one gRPC message of at most 8 MiB, however
// many evaluation frames a shot measures and however large they are.
TEST(EvaluateTask, TheContactSheetOfManyLargeEvaluationFramesFitsInAReport) {
  const FrameImage truth = test_support::smoothTruth(320, 180);
  std::vector<TaskInput> inputs;
  for (int64_t frame = 0; frame < 16; ++frame) {  // 16 rows of noisy 320x180 panels: 15 MB as pixels
    const auto seed = static_cast<uint64_t>(3 * frame);
    inputs.push_back(evaluationInput(TASK_ASSEMBLE_FRAME, ROLE_REFERENCE, frame,
                                     test_support::noisyCopy(truth, 0.01, seed, true)));
    inputs.push_back(evaluationInput(TASK_ASSEMBLE_FRAME, ROLE_BASELINE, frame,
                                     test_support::noisyCopy(truth, 0.3, seed + 1, true)));
    inputs.push_back(evaluationInput(TASK_COMPOSITE, ROLE_UNSPECIFIED, frame,
                                     test_support::noisyCopy(truth, 0.1, seed + 2, false)));
  }
  const std::string sheet = runEvaluateTask(Lease(), inputs).chunk;
  EXPECT_EQ(sheet.substr(1, 3), "PNG");
  EXPECT_LT(sheet.size(), 6'500'000u);
}

}  // namespace
}  // namespace pathfarm::farm
