#include "scheduler/shot_report.h"

#include <gtest/gtest.h>

#include <utility>
#include <vector>

#include "scheduler/task_records.h"

namespace pathfarm::farm {
namespace {

ShotSpec spec() {
  ShotSpec s;
  s.set_name("shot");
  s.set_pipeline(PIPELINE_DUI);
  s.set_frame_start(0);
  s.set_frame_end(3);
  s.set_width(10);
  s.set_height(10);
  s.set_spp(8);
  s.set_keyframe_interval(3);
  s.add_evaluation_frames(1);
  return s;
}

TEST(ShotReport, CostsRatesAndErrorsFollowFromTheTasks) {
  std::vector<TaskRecord> tasks;
  tasks.push_back(taskRecord(TASK_RENDER_TILE, ROLE_KEYFRAME, 0, 2.0));
  tasks.back().metrics["samples"] = 200;
  tasks.push_back(taskRecord(TASK_ASSEMBLE_FRAME, ROLE_KEYFRAME, 0, 1.0));
  tasks.push_back(taskRecord(TASK_DENOISE, ROLE_UNSPECIFIED, 0, 0.5));
  tasks.push_back(taskRecord(TASK_UPSAMPLE, ROLE_UNSPECIFIED, 0, 9.0, false));  // not done: counts nothing
  tasks.push_back(taskRecord(TASK_INTERPOLATE, ROLE_UNSPECIFIED, 1, 1.0));
  tasks.back().metrics = {{"rerender_pixels", 10}, {"rerender_holes", 4}};
  tasks.push_back(taskRecord(TASK_RENDER_TILE, ROLE_RERENDER, 1, 0.5));
  tasks.back().metrics["samples"] = 80;
  tasks.push_back(taskRecord(TASK_COMPOSITE, ROLE_UNSPECIFIED, 1, 0.5));
  tasks.back().metrics["rerender_pixels"] = 10;
  tasks.push_back(taskRecord(TASK_RENDER_TILE, ROLE_BASELINE, 1, 3.0));
  tasks.back().metrics["samples"] = 800;  // measurement: not traced for the output
  tasks.push_back(taskRecord(TASK_ASSEMBLE_FRAME, ROLE_BASELINE, 1, 1.0));
  tasks.push_back(taskRecord(TASK_EVALUATE, ROLE_UNSPECIFIED, 0, 0.25));
  tasks.back().metrics = {{"relmse.final", 0.01},     {"relmse.baseline", 0.03},     {"temporal.final", 0.02},
                          {"worst_tile.final", 0.5}, {"worst_share.final", 0.25}, {"relmse.interpolate", 0.2},
                          {"kept.interpolate", 0.9},  {"truth.final", 0.008},     {"truth_low.final", 0.007},
                          {"truth_high.final", 0.009}, {"truth.baseline", 0.028}, {"truth_low.baseline", 0.026},
                          {"truth_high.baseline", 0.03}, {"error_ratio", 0.3},    {"error_ratio_low", 0.25},
                          {"error_ratio_high", 0.35}};

  ShotSummary summary;
  summary.set_id(7);
  summary.set_state(SHOT_DONE);
  const ShotReport report = buildReport(summary, spec(), tasks);

  EXPECT_EQ(report.tasks_done(), 9);
  EXPECT_EQ(report.tasks_total(), 10);
  EXPECT_EQ(report.keyframes(), 2);  // frames 0 and 3
  const double total = 2.0 + 1.0 + 0.5 + 1.0 + 0.5 + 0.5;
  EXPECT_DOUBLE_EQ(report.core_seconds(), total);
  EXPECT_DOUBLE_EQ(report.core_seconds_per_frame(), total / 4);
  EXPECT_DOUBLE_EQ(report.baseline_core_seconds_per_frame(), 4.0);  // (3 + 1) core-seconds for 1 frame
  EXPECT_DOUBLE_EQ(report.relative_cost(), total / 4 / 4.0);
  EXPECT_DOUBLE_EQ(report.samples_traced(), 280);
  EXPECT_DOUBLE_EQ(report.resolution_gain(), 4.0 * 100 * 8 / 280);
  EXPECT_DOUBLE_EQ(report.overhead(), report.relative_cost() * report.resolution_gain());
  EXPECT_DOUBLE_EQ(report.measurement_core_seconds(), 3.0 + 1.0 + 0.25);
  EXPECT_DOUBLE_EQ(report.rerender_rate(), 10.0 / 400);
  EXPECT_DOUBLE_EQ(report.interpolation_rerender_rate(), 10.0 / 100);
  EXPECT_DOUBLE_EQ(report.interpolation_rerender_causes().at("holes"), 0.04);
  ASSERT_EQ(report.stages_size(), 5);  // render, denoise, interpolate, re-render, composite: no upsample done
  EXPECT_EQ(report.stages(0).stage(), "render");
  EXPECT_DOUBLE_EQ(report.stages(0).core_seconds(), 3.0);
  EXPECT_EQ(report.stages(3).stage(), "re-render");
  ASSERT_EQ(report.errors_size(), 3);
  EXPECT_EQ(report.errors(0).stage(), "interpolate");
  EXPECT_DOUBLE_EQ(report.errors(0).kept(), 0.9);
  EXPECT_EQ(report.errors(1).stage(), "final");
  EXPECT_DOUBLE_EQ(report.errors(1).relmse(), 0.01);
  EXPECT_DOUBLE_EQ(report.errors(1).worst_tile_relmse(), 0.5);
  EXPECT_DOUBLE_EQ(report.errors(1).worst_percent_share(), 0.25);
  EXPECT_DOUBLE_EQ(report.errors(1).kept(), 1.0);  // a stage that flags nothing is measured everywhere
  EXPECT_DOUBLE_EQ(report.temporal_error(), 0.02);
  EXPECT_EQ(report.baseline_temporal_error(), -1);

  const std::string md = reportMarkdown(report);
  EXPECT_NE(md.find("| **relative cost**"), std::string::npos);
  EXPECT_NE(md.find("| re-render samples per pixel | 8 |"), std::string::npos) << md;  // the shot's spp
  EXPECT_NE(md.find("| **final frames** | 0.01000 | 0.00800 (0.00700 to 0.00900) | 0.5000 | - | 25% | all |"),
            std::string::npos)
      << md;
  EXPECT_NE(
      md.find("| in-between frames interpolated | 0.20000 | - | 0.0000 | - | 0% | 90.0% (kept, not re-rendered) |"),
      std::string::npos);
  EXPECT_EQ(md.find("contact_sheet.png"), std::string::npos);  // no sheet, no picture
  ShotReport withSheet = report;
  withSheet.set_contact_sheet_png("\x89PNG...");
  EXPECT_NE(reportMarkdown(withSheet).find("![contact sheet](contact_sheet.png)"), std::string::npos);
  EXPECT_EQ(reportJson(withSheet).find("iVBOR"), std::string::npos);  // the bytes (base64) stay out of the JSON
  EXPECT_NE(reportJson(report).find("\"relative_cost\""), std::string::npos);

  // An error 0.3 of pt's against the truth: pt would need 1/0.3 the samples for it.
  EXPECT_DOUBLE_EQ(report.cost_at_equal_error(), report.relative_cost() * 0.3);
  EXPECT_DOUBLE_EQ(report.cost_at_equal_error_interval().low(), report.relative_cost() * 0.25);
  EXPECT_DOUBLE_EQ(report.cost_at_equal_error_interval().high(), report.relative_cost() * 0.35);
  EXPECT_DOUBLE_EQ(report.errors(1).truth_error().low(), 0.007);
  EXPECT_EQ(report.verdict().rfind("dui paid off: 0.10 (0.09 to 0.12) of plain pt's core-seconds for the same error", 0),
            0u)
      << report.verdict();
  EXPECT_NE(md.find("**Verdict:** dui paid off"), std::string::npos);
  // Why the farm ran another pipeline than the shot file named heads the report.
  ShotReport switched = report;
  switched.set_pipeline("d");
  switched.set_pipeline_reason("the shot asked for dui");
  EXPECT_NE(reportMarkdown(switched).find("Pipeline `d` (the shot asked for dui), "), std::string::npos);
  EXPECT_EQ(md.find("Pipeline `dui` ("), std::string::npos);
}

TEST(ShotReport, PtsCostPerFrameIsPerRenderWhenTheBaselineIsRenderedSeveralTimes) {
  std::vector<TaskRecord> tasks;
  tasks.push_back(taskRecord(TASK_RENDER_TILE, ROLE_KEYFRAME, 0, 8.0));
  for (int repeat = 0; repeat < 3; ++repeat) {
    tasks.push_back(taskRecord(TASK_RENDER_TILE, ROLE_BASELINE, 1, 1.5 + repeat));
    tasks.back().params.set_baseline_repeat(repeat);
    tasks.push_back(taskRecord(TASK_ASSEMBLE_FRAME, ROLE_BASELINE, 1, 0.5));
    tasks.back().params.set_baseline_repeat(repeat);
  }
  const ShotReport report = buildReport(ShotSummary(), spec(), tasks);
  EXPECT_DOUBLE_EQ(report.baseline_core_seconds_per_frame(), (1.5 + 2.5 + 3.5 + 3 * 0.5) / 3);
  EXPECT_EQ(report.baseline_source(), "measured: pt at 8 spp on 1 frame(s), 3 independent renders");
}

// The report of two upsampled keyframes of 10x10 pixels, the first's tasks given, the
// second's one task re-rendering 20 pixels, 12 on edges of directly seen light and 4 on
// moving caustics.
ShotReport reportOfTwoKeyframes(std::vector<TaskRecord> firstKeyframe) {
  std::vector<TaskRecord> tasks = std::move(firstKeyframe);
  tasks.push_back(taskRecord(TASK_UPSAMPLE, ROLE_UNSPECIFIED, 3, 1.0));
  tasks.back().metrics = {{"rerender_pixels", 20}, {"rerender_light_edges", 12}, {"rerender_moving_caustics", 4}};
  ShotSummary summary;
  summary.set_state(SHOT_DONE);
  return buildReport(summary, spec(), tasks);
}

TEST(ShotReport, AnUpsampledKeyframesReRenderIsSplitByCause) {
  // The first keyframe re-renders 10 pixels, 8 on light edges and 2 on caustics: 30 in
  // all, 20 and 6 (the rest flagged by the upsampler itself).
  std::vector<TaskRecord> first = {taskRecord(TASK_UPSAMPLE, ROLE_UNSPECIFIED, 0, 1.0)};
  first.back().metrics = {{"rerender_pixels", 10}, {"rerender_light_edges", 8}, {"rerender_moving_caustics", 2}};
  const ShotReport report = reportOfTwoKeyframes(first);
  EXPECT_DOUBLE_EQ(report.upsample_rerender_rate(), 30.0 / 200);
  EXPECT_DOUBLE_EQ(report.upsample_rerender_causes().at("light_edges"), 20.0 / 200);
  EXPECT_DOUBLE_EQ(report.upsample_rerender_causes().at("moving_caustics"), 6.0 / 200);
  const std::string markdown = reportMarkdown(report);
  const size_t rate = markdown.find("| re-render rate, upsampled keyframes | 15.00% |");
  ASSERT_NE(rate, std::string::npos) << markdown;
  EXPECT_NE(markdown.find("| &nbsp; of which light_edges | 10.00% |", rate), std::string::npos) << markdown;
}

TEST(ShotReport, AFrameFilteredInWindowsCountsAsOneFrameWithItsWindowsCauses) {
  // The first keyframe of the test above in two windows of rows, which count its causes
  // (8 on light edges, 2 on caustics), and their join, which counts its re-render (10);
  // an in-between frame the same way, beside it.
  std::vector<TaskRecord> first;
  for (const TaskKind kind : {TASK_UPSAMPLE, TASK_INTERPOLATE}) {
    for (const auto& [edges, caustics] : {std::pair{5, 2}, std::pair{3, 0}}) {
      first.push_back(taskRecord(kind, ROLE_UNSPECIFIED, kind == TASK_UPSAMPLE ? 0 : 1, 0.5));
      first.back().params.mutable_window()->set_x1(10);
      first.back().params.mutable_window()->set_y1(5);
      first.back().metrics = {{"rerender_light_edges", edges}, {"rerender_moving_caustics", caustics}};
    }
    first.push_back(taskRecord(kind, ROLE_UNSPECIFIED, kind == TASK_UPSAMPLE ? 0 : 1, 0.1));
    first.back().metrics = {{"rerender_pixels", 10}, {"pixels", 100}};
  }
  const ShotReport report = reportOfTwoKeyframes(first);
  EXPECT_DOUBLE_EQ(report.upsample_rerender_rate(), 30.0 / 200);
  EXPECT_DOUBLE_EQ(report.upsample_rerender_causes().at("light_edges"), 20.0 / 200);
  EXPECT_DOUBLE_EQ(report.upsample_rerender_causes().at("moving_caustics"), 6.0 / 200);
  EXPECT_DOUBLE_EQ(report.interpolation_rerender_rate(), 10.0 / 100);  // one frame of 100 pixels
  EXPECT_DOUBLE_EQ(report.interpolation_rerender_causes().at("light_edges"), 8.0 / 100);
}

TEST(ShotReport, TheVerdictSaysPlainlyWhenThePipelineLost) {
  std::vector<TaskRecord> tasks;
  tasks.push_back(taskRecord(TASK_RENDER_TILE, ROLE_KEYFRAME, 0, 16.0));  // 4 core-seconds per frame
  tasks.push_back(taskRecord(TASK_RENDER_TILE, ROLE_BASELINE, 1, 1.5));   // pt: 2 per frame
  tasks.push_back(taskRecord(TASK_ASSEMBLE_FRAME, ROLE_BASELINE, 1, 0.5));
  tasks.push_back(taskRecord(TASK_EVALUATE, ROLE_UNSPECIFIED, 0, 0.25));
  tasks.back().metrics = {{"relmse.final", 0.02},
                          {"relmse.baseline", 0.01},
                          {"truth.final", 0.02},
                          {"truth_low.final", 0.018},
                          {"truth_high.final", 0.022},
                          {"truth.baseline", 0.01},
                          {"truth_low.baseline", 0.009},
                          {"truth_high.baseline", 0.011},
                          {"error_ratio", 2.0},
                          {"error_ratio_low", 1.7},
                          {"error_ratio_high", 2.3},
                          {"worst_tile_truth.final", 3.0},
                          {"worst_tile_truth_low.final", 2.5},
                          {"worst_tile_truth_high.final", 3.5},
                          {"worst_tile_truth.baseline", 0.5},
                          {"worst_tile_truth_low.baseline", 0.4},
                          {"worst_tile_truth_high.baseline", 0.6},
                          {"temporal_truth.final", 0.2},
                          {"temporal_truth_low.final", 0.15},
                          {"temporal_truth.baseline", 0.1},
                          {"temporal_truth_high.baseline", 0.12}};
  const ShotReport report = buildReport(ShotSummary(), spec(), tasks);
  EXPECT_DOUBLE_EQ(report.relative_cost(), 2.0);
  EXPECT_DOUBLE_EQ(report.cost_at_equal_error(), 4.0);  // twice the cost at twice the error
  const std::string& verdict = report.verdict();
  EXPECT_EQ(verdict.rfind("dui did not pay off: it cost 4.00 (3.40 to 4.60)x what plain pt would for the same error", 0),
            0u)
      << verdict;
  EXPECT_NE(verdict.find("worst 16x16 tile has 6.0x pt's"), std::string::npos) << verdict;
  EXPECT_NE(verdict.find("flickers more than pt"), std::string::npos) << verdict;
  EXPECT_EQ(verdict.find("cannot be told"), std::string::npos) << verdict;
  EXPECT_EQ(verdict.find("coarsely"), std::string::npos) << verdict;
  EXPECT_EQ(report.reference_noise(), -1);  // not measured

  // A reference whose noise is more than a tenth of the error it measures says so, and
  // what would resolve it: at 256 spp a noise of 0.005 against an error of 0.02 needs
  // 256 x 10 x 0.005 / 0.02 = 640, so 1024 spp.
  ShotSpec withReference = spec();
  withReference.set_reference_spp(256);
  tasks.back().metrics["reference_noise"] = 0.005;
  const ShotReport coarse = buildReport(ShotSummary(), withReference, tasks);
  EXPECT_NE(coarse.verdict().find("resolves its error only coarsely: the reference's noise 0.0050 is more than a "
                                  "tenth of it; a reference of 1024 spp would resolve it."),
            std::string::npos)
      << coarse.verdict();
  tasks.back().metrics["reference_noise"] = 0.0019;  // under a tenth of 0.02: resolved
  EXPECT_EQ(buildReport(ShotSummary(), withReference, tasks).verdict().find("coarsely"), std::string::npos);
  tasks.back().metrics.erase("reference_noise");

  // An interval that includes 1 claims nothing either way; overlapping tiles and temporal
  // errors claim no artifact and no flicker.
  tasks.back().metrics["error_ratio_low"] = 0.4;
  tasks.back().metrics["worst_tile_truth_low.final"] = 1.0;
  tasks.back().metrics["temporal_truth_low.final"] = 0.11;
  const ShotReport unsure = buildReport(ShotSummary(), spec(), tasks);
  EXPECT_EQ(unsure.verdict().rfind("Cannot tell at this reference whether dui paid off", 0), 0u) << unsure.verdict();
  EXPECT_NE(unsure.verdict().find("0.80 to 4.60"), std::string::npos) << unsure.verdict();
  EXPECT_EQ(unsure.verdict().find("worst 16x16"), std::string::npos) << unsure.verdict();
  EXPECT_EQ(unsure.verdict().find("flickers"), std::string::npos) << unsure.verdict();

  // A baseline error that cannot be told from 0: nothing to compare against.
  tasks.back().metrics["reference_noise"] = 0.0125;
  tasks.back().metrics["truth_low.baseline"] = -0.001;
  const ShotReport atTheFloor = buildReport(ShotSummary(), spec(), tasks);
  EXPECT_DOUBLE_EQ(atTheFloor.reference_noise(), 0.0125);
  EXPECT_EQ(atTheFloor.verdict().rfind("The errors cannot be told from the reference's own noise (0.0125)", 0), 0u)
      << atTheFloor.verdict();
  EXPECT_NE(reportMarkdown(atTheFloor).find("| the reference's own noise (its expected relMSE, included in every "
                                            "relMSE above) | 0.01250 |"),
            std::string::npos);
  EXPECT_EQ(atTheFloor.cost_at_equal_error(), -1);
  // A ratio the evaluation could not bound at all is left out of its figures: the same.
  tasks.back().metrics["truth_low.baseline"] = 0.009;
  const double ratio = tasks.back().metrics["error_ratio"];
  tasks.back().metrics.erase("error_ratio");
  EXPECT_EQ(buildReport(ShotSummary(), spec(), tasks).verdict().rfind("The errors cannot be told", 0), 0u);
  tasks.back().metrics["error_ratio"] = ratio;
  // A ratio unbounded above (the evaluation leaves the infinite end out) pays off never.
  tasks.back().metrics["truth_low.baseline"] = 0.009;
  tasks.back().metrics.erase("error_ratio_high");
  tasks.back().metrics["error_ratio"] = 0.2;
  tasks.back().metrics["error_ratio_low"] = 0.1;
  const ShotReport unbounded = buildReport(ShotSummary(), spec(), tasks);
  EXPECT_EQ(unbounded.verdict().rfind("Cannot tell", 0), 0u) << unbounded.verdict();
  EXPECT_NE(unbounded.verdict().find("to infinity"), std::string::npos) << unbounded.verdict();

  // No reference, no verdict; pt is its own baseline.
  tasks.pop_back();
  EXPECT_TRUE(buildReport(ShotSummary(), spec(), tasks).verdict().empty());
  EXPECT_EQ(buildReport(ShotSummary(), spec(), tasks).cost_at_equal_error(), -1);
}

TEST(ShotReport, APtShotIsItsOwnBaselineAndAGivenCostIsUsed) {
  ShotSpec pt = spec();
  pt.set_pipeline(PIPELINE_PT);
  std::vector<TaskRecord> tasks = {taskRecord(TASK_RENDER_TILE, ROLE_OUTPUT, 0, 6.0),
                                   taskRecord(TASK_ASSEMBLE_FRAME, ROLE_OUTPUT, 0, 2.0)};
  tasks[0].metrics["samples"] = 3200;
  const ShotReport own = buildReport({}, pt, tasks);
  EXPECT_DOUBLE_EQ(own.relative_cost(), 1.0);
  EXPECT_EQ(own.rerender_spp(), 0);  // pt re-renders nothing
  EXPECT_EQ(reportMarkdown(own).find("re-render samples"), std::string::npos);
  EXPECT_DOUBLE_EQ(own.resolution_gain(), 1.0);

  ShotSpec given = spec();
  given.set_baseline_core_seconds(8.0);
  const ShotReport report = buildReport({}, given, tasks);
  EXPECT_EQ(report.baseline_source(), "given in the shot");
  EXPECT_DOUBLE_EQ(report.relative_cost(), 8.0 / 4 / 8.0);
}

}  // namespace
}  // namespace pathfarm::farm
