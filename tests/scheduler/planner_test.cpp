#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <tuple>

#include "renderer/integrators/frame_integrator.h"
#include "scheduler/planner.h"

namespace pathfarm::farm {
namespace {

ShotSpec renderSpec() {
  ShotSpec spec;
  spec.set_pipeline(PIPELINE_PT);
  spec.set_frame_start(3);
  spec.set_frame_end(4);
  spec.set_width(100);
  spec.set_height(70);
  spec.set_spp(4);
  spec.set_tile(32);
  return spec;
}

TEST(Planner, TilesCoverEachFrameOnceAndAssemblyWaitsForThem) {
  const auto plan = planShot(renderSpec());
  // 4 x 3 tiles per frame plus one assemble task, for 2 frames.
  ASSERT_EQ(plan.size(), 2u * (12 + 1));
  for (int64_t frame : {3, 4}) {
    std::vector<int> covered(100 * 70, 0);
    const PlannedTask* assemble = nullptr;
    for (size_t i = 0; i < plan.size(); ++i) {
      const PlannedTask& task = plan[i];
      if (task.params.frame() != frame) continue;
      if (task.kind == TASK_ASSEMBLE_FRAME) {
        assemble = &task;
        continue;
      }
      ASSERT_EQ(task.kind, TASK_RENDER_TILE);
      EXPECT_TRUE(task.dependencies.empty());
      const PixelWindow& w = task.params.window();
      for (int y = w.y0(); y < w.y1(); ++y)
        for (int x = w.x0(); x < w.x1(); ++x) ++covered[static_cast<size_t>(y * 100 + x)];
    }
    for (int c : covered) ASSERT_EQ(c, 1);
    ASSERT_NE(assemble, nullptr);
    std::set<size_t> deps(assemble->dependencies.begin(), assemble->dependencies.end());
    EXPECT_EQ(deps.size(), 12u);
    for (size_t d : deps) {
      EXPECT_EQ(plan[d].params.frame(), frame);
      EXPECT_LT(d, static_cast<size_t>(assemble - plan.data()));  // dependencies come first
    }
  }
}

TEST(Planner, AShotBeyondTheSchedulersLimitsIsRefusedBeforeItIsPlanned) {
  const ShotLimits limits;  // the defaults: 1e6 frames, 1e12 pixel-frames, 1e6 tasks
  const auto refusal = [&](const ShotSpec& spec) {
    try {
      planShotWithin(spec, limits);
    } catch (const PlanError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  ShotSpec spec = renderSpec();
  EXPECT_EQ(refusal(spec), "accepted");
  spec.set_frame_end(int64_t{3'000'000'000});  // a typo: billions of frames, refused before any is planned
  EXPECT_NE(refusal(spec).find("frames: 2999999998 frames is more than this scheduler takes"), std::string::npos)
      << refusal(spec);
  spec = renderSpec();
  spec.set_width(16384);
  spec.set_height(16384);
  spec.set_frame_end(10'000);  // 2.7e12 pixel-frames
  EXPECT_NE(refusal(spec).find("pixel-frames is more than"), std::string::npos) << refusal(spec);
  spec = renderSpec();
  spec.set_width(8192);
  spec.set_height(4096);
  spec.set_tile(8);  // half a million tiles a frame
  EXPECT_NE(refusal(spec).find("plans at least 1048578 tasks, more than this scheduler takes (1000000"),
            std::string::npos)
      << refusal(spec);
  ShotLimits generous;
  generous.maxTasks = 2'000'000;
  // 2 frames of 1024 x 512 tiles, each assembled from 128 regions of 4 rows of tiles.
  EXPECT_EQ(planShotWithin(spec, generous).size(), 2u * (1024 * 512 + 128 + 1));
}

// Found with the shot_json fuzz target: within the frame and pixel-frame limits, 8-pixel
// tiles planned 1.6e10 tasks (minutes and gigabytes) before the task limit was checked. The
// tiles are counted first.
TEST(Planner, AShotOfTooManyTilesIsRefusedBeforeAnyIsPlanned) {
  ShotLimits limits;
  limits.maxTasks = 1000;
  ShotSpec spec = renderSpec();
  spec.set_frame_end(spec.frame_start() + 15);
  spec.set_width(1024);
  spec.set_height(1024);
  spec.set_tile(8);  // 16 frames of 16384 tiles and an assembly
  EXPECT_EQ(plannedTasksAtLeast(spec), 16 * (16384 + 1));
  try {
    planShotWithin(spec, limits);
    FAIL() << "a shot of 262160 tasks was planned within a limit of 1000";
  } catch (const PlanError& e) {
    ASSERT_NE(std::string(e.what()).find("plans at least 262160 tasks, more than this scheduler takes (1000"),
              std::string::npos)
        << e.what();
  }
  spec.set_frame_end(spec.frame_start() + 999'999);
  spec.set_width(1000);
  spec.set_height(1000);  // 10^12 pixel-frames, the default limit: 1.6e10 tiles
  EXPECT_EQ(plannedTasksAtLeast(spec), int64_t{1'000'000} * (125 * 125 + 1));
  EXPECT_THROW(planShotWithin(spec, ShotLimits{}), PlanError);
  spec.set_pipeline(PIPELINE_TMLT);  // no tiles: a window's tasks and a merge per frame
  EXPECT_EQ(plannedTasksAtLeast(spec), 1'000'000);
}

TEST(Planner, RefusesWhatItCannotRun) {
  ShotSpec spec = renderSpec();
  spec.set_pipeline(static_cast<Pipeline>(99));  // a value from a newer client
  try {
    planShot(spec);
    FAIL() << "an unknown pipeline was planned";
  } catch (const PlanError& e) {
    EXPECT_NE(std::string(e.what()).find("unknown pipeline 99 is not available (this farm runs: auto, pt, d,"), std::string::npos)
        << e.what();
  }
  spec.set_pipeline(PIPELINE_UNSPECIFIED);
  EXPECT_THROW(planShot(spec), PlanError);
  spec.set_pipeline(PIPELINE_DUI);  // without a decomposition
  EXPECT_THROW(planShot(spec), PlanError);
  spec = renderSpec();
  spec.set_frame_end(2);
  EXPECT_THROW(planShot(spec), PlanError);
  for (const auto& [zoom, x, y] : std::vector<std::tuple<double, double, double>>{
           {std::nan(""), 0, 0}, {-1, 0, 0}, {4, 0.6, 0}, {4, 0, -0.75}, {4, std::nan(""), 0}}) {
    spec = renderSpec();
    spec.set_camera_zoom(zoom);
    spec.set_camera_shift_x(x);
    spec.set_camera_shift_y(y);
    EXPECT_THROW(planShot(spec), PlanError) << "a camera window outside the picture: " << zoom << " " << x << " " << y;
  }
  spec = renderSpec();
  spec.set_camera_zoom(4);
  spec.set_camera_shift_x(0.25);
  spec.set_camera_shift_y(-0.25);
  EXPECT_NO_THROW(planShot(spec)) << "a window in the top right quarter";
  spec = renderSpec();
  spec.set_tile(0);
  EXPECT_THROW(planShot(spec), PlanError);
  spec.set_pipeline(PIPELINE_NOOP);
  spec.set_noop_tasks(5);
  EXPECT_EQ(planShot(spec).size(), 5u);
}

// A filtering shot: frames 10..19 (10 frames) at 64x32 in 32-pixel tiles (2 per frame).
ShotSpec filteringSpec(const std::string& pipeline, int interval) {
  ShotSpec spec = renderSpec();
  spec.set_pipeline(*pipelineNamed(pipeline));
  spec.set_frame_start(10);
  spec.set_frame_end(19);
  spec.set_width(64);
  spec.set_height(32);
  spec.set_spp(16);
  spec.set_decompose("diffuse_direct=ED,diffuse_indirect=ED.+,reflection=ERD.*,residual");
  spec.set_keyframe_interval(interval);
  spec.set_feature_spp(2);
  return spec;
}

std::map<TaskKind, int> countKinds(const std::vector<PlannedTask>& plan) {
  std::map<TaskKind, int> counts;
  for (const PlannedTask& task : plan) ++counts[task.kind];
  return counts;
}

// The frames of the tasks `task` depends on that have kind `kind`.
std::set<int64_t> dependencyFrames(const std::vector<PlannedTask>& plan, const PlannedTask& task, TaskKind kind) {
  std::set<int64_t> frames;
  for (const size_t d : task.dependencies)
    if (plan[d].kind == kind) frames.insert(plan[d].params.frame());
  return frames;
}

TEST(Planner, DuiGraphHasEveryStageWithItsEdges) {
  // k = 4: keyframes 10, 14, 18 and the last frame 19; in-between 11-13 and 15-17.
  const auto plan = planShot(filteringSpec("dui", 4));
  auto counts = countKinds(plan);
  EXPECT_EQ(counts[TASK_RENDER_TILE], 10 * 2);  // 4 keyframes, 6 in-between frames' features
  EXPECT_EQ(counts[TASK_ASSEMBLE_FRAME], 10);
  EXPECT_EQ(counts[TASK_DENOISE], 4);
  EXPECT_EQ(counts[TASK_UPSAMPLE], 4);
  EXPECT_EQ(counts[TASK_FLOW], 2 * 3);    // (10,14), (14,18) x diffuse_direct, diffuse_indirect, residual
  EXPECT_EQ(counts[TASK_INTERPOLATE], 6);
  EXPECT_EQ(counts[TASK_COMPOSITE], 10);
  EXPECT_EQ(counts[TASK_EVALUATE], 0);    // no reference asked for
  int outputs = 0;
  for (size_t i = 0; i < plan.size(); ++i) {
    const PlannedTask& task = plan[i];
    for (const size_t d : task.dependencies) EXPECT_LT(d, i);
    outputs += task.output;
    EXPECT_EQ(task.output, task.kind == TASK_COMPOSITE);
    if (task.kind == TASK_RENDER_TILE && task.params.role() == ROLE_FEATURES) {
      EXPECT_EQ(task.params.spp(), 2);              // feature_spp
      EXPECT_EQ(task.params.reflectance_spp(), 4);  // the keyframes'
      EXPECT_TRUE(task.params.frame() != 10 && task.params.frame() != 14 && task.params.frame() != 18 &&
                  task.params.frame() != 19);
    } else if (task.kind == TASK_RENDER_TILE) {
      EXPECT_EQ(task.params.role(), ROLE_KEYFRAME);
      EXPECT_EQ(task.params.spp(), 4);  // a quarter of the samples
      // Motion vectors reach the neighbouring keyframes: 10 <-> 14 <-> 18 <-> 19.
      const std::map<int64_t, std::pair<int, int>> spans = {{10, {4, 1}}, {14, {4, 4}}, {18, {1, 4}}, {19, {1, 1}}};
      const auto& [forward, backward] = spans.at(task.params.frame());
      EXPECT_EQ(task.params.motion_forward(), forward) << "frame " << task.params.frame();
      EXPECT_EQ(task.params.motion_backward(), backward) << "frame " << task.params.frame();
    }
    if (task.kind == TASK_DENOISE && task.params.frame() == 14) {
      EXPECT_EQ(dependencyFrames(plan, task, TASK_ASSEMBLE_FRAME), (std::set<int64_t>{10, 14, 18}));
    }
    if (task.kind == TASK_DENOISE && task.params.frame() == 19) {
      EXPECT_EQ(dependencyFrames(plan, task, TASK_ASSEMBLE_FRAME), (std::set<int64_t>{18, 19}));
    }
    if (task.kind == TASK_FLOW) {
      EXPECT_EQ(dependencyFrames(plan, task, TASK_UPSAMPLE),
                (std::set<int64_t>{task.params.keyframe_before(), task.params.keyframe_after()}));
      EXPECT_EQ(task.params.keyframe_after() - task.params.keyframe_before(), 4);
    }
    if (task.kind == TASK_INTERPOLATE && task.params.frame() == 16) {
      EXPECT_EQ(task.params.keyframe_before(), 14);
      EXPECT_EQ(task.params.keyframe_after(), 18);
      EXPECT_EQ(dependencyFrames(plan, task, TASK_UPSAMPLE), (std::set<int64_t>{14, 18}));
      EXPECT_EQ(dependencyFrames(plan, task, TASK_FLOW), (std::set<int64_t>{14}));  // flows are keyed by K0
      EXPECT_EQ(dependencyFrames(plan, task, TASK_ASSEMBLE_FRAME), (std::set<int64_t>{16}));  // its features
      int flows = 0;
      for (const size_t d : task.dependencies) flows += plan[d].kind == TASK_FLOW;
      EXPECT_EQ(flows, 3);
    }
    if (task.kind == TASK_COMPOSITE) {
      ASSERT_EQ(task.dependencies.size(), 1u);
      const TaskKind stage = plan[task.dependencies[0]].kind;
      const int64_t frame = task.params.frame();
      const bool keyframe = frame == 10 || frame == 14 || frame == 18 || frame == 19;
      EXPECT_EQ(stage, keyframe ? TASK_UPSAMPLE : TASK_INTERPOLATE) << "frame " << frame;
    }
  }
  EXPECT_EQ(outputs, 10);
}

TEST(Planner, EachPipelinePlansOnlyItsStages) {
  const auto d = countKinds(planShot(filteringSpec("d", 4)));
  EXPECT_EQ(d.count(TASK_UPSAMPLE) + d.count(TASK_INTERPOLATE) + d.count(TASK_FLOW), 0u);
  EXPECT_EQ(d.at(TASK_DENOISE), 10);  // every frame is a keyframe
  EXPECT_EQ(d.count(TASK_COMPOSITE), 0u);  // nothing is re-rendered: the denoise writes the frame
  for (const PlannedTask& task : planShot(filteringSpec("d", 4))) {
    EXPECT_EQ(task.output, task.kind == TASK_DENOISE);
    if (task.kind == TASK_DENOISE) {
      EXPECT_EQ(task.params.role(), ROLE_OUTPUT);
    }
  }
  const auto du = countKinds(planShot(filteringSpec("du", 4)));
  EXPECT_EQ(du.at(TASK_UPSAMPLE), 10);
  EXPECT_EQ(du.count(TASK_INTERPOLATE), 0u);
  const auto di = countKinds(planShot(filteringSpec("di", 4)));
  EXPECT_EQ(di.count(TASK_UPSAMPLE), 0u);
  EXPECT_EQ(di.at(TASK_INTERPOLATE), 6);
  ShotSpec manySamples = filteringSpec("di", 4);
  manySamples.set_spp(64);
  for (const PlannedTask& task : planShot(manySamples))
    if (task.kind == TASK_RENDER_TILE && task.params.role() == ROLE_KEYFRAME) {
      EXPECT_EQ(task.params.spp(), 64);
    } else if (task.kind == TASK_RENDER_TILE) {
      EXPECT_EQ(task.params.spp(), 2);  // feature_spp
      EXPECT_EQ(task.params.reflectance_spp(), kMaxOwnReflectanceSpp);  // not the keyframes' 64
      EXPECT_LT(kMaxOwnReflectanceSpp, 64);
    }
  // Upsampling needs an even resolution.
  ShotSpec odd = filteringSpec("du", 4);
  odd.set_width(63);
  EXPECT_THROW(planShot(odd), PlanError);
  odd.set_pipeline(PIPELINE_DI);
  EXPECT_NO_THROW(planShot(odd));
}

TEST(Planner, OneFrameAndShortShotsAreHandled) {
  ShotSpec one = filteringSpec("dui", 8);
  one.set_frame_end(10);
  const auto single = countKinds(planShot(one));
  EXPECT_EQ(single.at(TASK_DENOISE), 1);
  EXPECT_EQ(single.at(TASK_COMPOSITE), 1);
  EXPECT_EQ(single.count(TASK_FLOW) + single.count(TASK_INTERPOLATE), 0u);

  // Shorter than one interval: the first and the last frame are the keyframes.
  ShotSpec shortShot = filteringSpec("dui", 8);
  shortShot.set_frame_end(14);
  EXPECT_EQ(keyframesOf(shortShot), (std::vector<int64_t>{10, 14}));
  const auto shortCounts = countKinds(planShot(shortShot));
  EXPECT_EQ(shortCounts.at(TASK_FLOW), 3);
  EXPECT_EQ(shortCounts.at(TASK_INTERPOLATE), 3);
  EXPECT_EQ(shortCounts.at(TASK_COMPOSITE), 5);

  // k = 1 interpolates nothing.
  const auto everyFrame = countKinds(planShot(filteringSpec("dui", 1)));
  EXPECT_EQ(everyFrame.count(TASK_INTERPOLATE) + everyFrame.count(TASK_FLOW), 0u);
  EXPECT_EQ(everyFrame.at(TASK_UPSAMPLE), 10);
}

TEST(Planner, EvaluationAddsBaselineReferenceAndOneEvaluateTask) {
  ShotSpec spec = filteringSpec("dui", 4);
  spec.add_evaluation_frames(12);
  spec.add_evaluation_frames(13);
  // Without a reference: the baseline's cost is measured on the evaluation frames.
  auto counts = countKinds(planShot(spec));
  EXPECT_EQ(counts.count(TASK_EVALUATE), 0u);
  int baseline = 0;
  for (const PlannedTask& task : planShot(spec))
    if (task.params.role() == ROLE_BASELINE) {
      ++baseline;
      EXPECT_TRUE(task.params.beauty_only() || task.kind == TASK_ASSEMBLE_FRAME);
      if (task.kind == TASK_RENDER_TILE) {
        EXPECT_EQ(task.params.spp(), 16);
      }
    }
  EXPECT_EQ(baseline, 2 * 3);  // two frames of 2 tiles + assembly
  spec.set_baseline_core_seconds(12.5);
  for (const PlannedTask& task : planShot(spec)) EXPECT_NE(task.params.role(), ROLE_BASELINE);

  spec.set_reference_spp(256);
  const auto plan = planShot(spec);
  counts = countKinds(plan);
  ASSERT_EQ(counts.at(TASK_EVALUATE), 1);
  const PlannedTask& evaluate = plan.back();
  ASSERT_EQ(evaluate.kind, TASK_EVALUATE);
  std::map<TaskRole, std::set<int64_t>> byRole;
  std::set<TaskKind> kinds;
  for (const size_t d : evaluate.dependencies) {
    byRole[plan[d].params.role()].insert(plan[d].params.frame());
    kinds.insert(plan[d].kind);
  }
  EXPECT_EQ(byRole[ROLE_REFERENCE], (std::set<int64_t>{12, 13}));
  EXPECT_EQ(byRole[ROLE_BASELINE], (std::set<int64_t>{12, 13}));
  EXPECT_EQ(kinds, (std::set<TaskKind>{TASK_ASSEMBLE_FRAME, TASK_INTERPOLATE, TASK_COMPOSITE}));

  spec.clear_evaluation_frames();
  spec.add_evaluation_frames(25);  // not in the shot
  EXPECT_THROW(planShot(spec), PlanError);
}

TEST(Planner, BaselineRepeatsRenderEachEvaluationFrameFromDisjointSampleRanges) {
  ShotSpec spec = filteringSpec("d", 1);
  spec.add_evaluation_frames(12);
  spec.add_evaluation_frames(13);
  spec.set_reference_spp(256);
  spec.set_baseline_repeats(3);
  const auto plan = planShot(spec);
  const PlannedTask& evaluate = plan.back();
  ASSERT_EQ(evaluate.kind, TASK_EVALUATE);
  // Every (frame, repeat) assembled once, from tiles of that repeat, and read by the evaluation.
  std::set<std::pair<int64_t, int>> assembled, evaluated;
  for (const PlannedTask& task : plan) {
    if (task.params.role() != ROLE_BASELINE || task.kind != TASK_ASSEMBLE_FRAME) continue;
    EXPECT_TRUE(assembled.insert({task.params.frame(), task.params.baseline_repeat()}).second);
    for (const size_t d : task.dependencies) {
      EXPECT_EQ(plan[d].params.baseline_repeat(), task.params.baseline_repeat());
      EXPECT_EQ(plan[d].params.spp(), 16);
    }
  }
  for (const size_t d : evaluate.dependencies)
    if (plan[d].params.role() == ROLE_BASELINE) evaluated.insert({plan[d].params.frame(), plan[d].params.baseline_repeat()});
  const std::set<std::pair<int64_t, int>> expected = {{12, 0}, {12, 1}, {12, 2}, {13, 0}, {13, 1}, {13, 2}};
  EXPECT_EQ(assembled, expected);
  EXPECT_EQ(evaluated, expected);

  spec.set_baseline_repeats(kMaxBaselineRepeats + 1);
  EXPECT_THROW(planShot(spec), PlanError);
  // Renders whose samples would run into the reference's are refused.
  spec.set_baseline_repeats(2);
  spec.set_first_sample(kIndependentFirstSample - 20);
  EXPECT_THROW(planShot(spec), PlanError);
  spec.set_first_sample(kIndependentFirstSample - 32);
  EXPECT_NO_THROW(planShot(spec));
}

TEST(Planner, AKnownReferenceIsHandedOnAndOnlyTheOtherFramesReferenceIsRendered) {
  ShotSpec spec = renderSpec();  // frames 3..4, 12 tiles a frame
  spec.set_reference_spp(256);
  spec.add_evaluation_frames(3);
  spec.add_evaluation_frames(4);
  KnownReference* known = spec.add_known_references();
  known->set_frame(4);
  known->mutable_chunk()->set_sha256(std::string(64, 'a'));
  const auto plan = planShot(spec);
  std::map<int64_t, int> referenceTiles;
  std::vector<const PlannedTask*> given;
  for (const PlannedTask& task : plan) {
    if (task.params.role() != ROLE_REFERENCE) continue;
    if (task.kind == TASK_RENDER_TILE) ++referenceTiles[task.params.frame()];
    if (task.params.has_given_frame()) given.push_back(&task);
  }
  EXPECT_EQ(referenceTiles, (std::map<int64_t, int>{{3, 12}}));
  ASSERT_EQ(given.size(), 1u);
  EXPECT_EQ(given[0]->kind, TASK_ASSEMBLE_FRAME);
  EXPECT_EQ(given[0]->params.frame(), 4);
  EXPECT_EQ(given[0]->params.given_frame().sha256(), std::string(64, 'a'));
  EXPECT_TRUE(given[0]->dependencies.empty());
  const size_t givenIndex = static_cast<size_t>(given[0] - plan.data());
  const auto& evaluated = plan.back().dependencies;
  EXPECT_NE(std::find(evaluated.begin(), evaluated.end(), givenIndex), evaluated.end()) << "the evaluation reads it";

  known->set_frame(3);
  spec.add_known_references()->set_frame(3);
  EXPECT_THROW(planShot(spec), PlanError) << "one frame given twice";
  spec.mutable_known_references()->RemoveLast();
  known->set_frame(5);
  EXPECT_THROW(planShot(spec), PlanError) << "a frame the shot does not evaluate";
}

TEST(Planner, TgptSamplesEachFrameInTilesThatCoverItOnceAndJoinsThem) {
  ShotSpec spec = renderSpec();  // 100 x 70, tiles of 32: 4 x 3 per frame
  spec.set_pipeline(PIPELINE_TGPT);
  spec.set_poisson_window(2);
  spec.set_poisson_norm("l1");
  const auto plan = planShot(spec);
  std::map<int64_t, int> joins;
  for (const PlannedTask& task : plan) {
    if (task.kind != TASK_GRADIENT_RENDER) continue;
    ++joins[task.params.frame()];
    std::vector<int> covered(100 * 70, 0);
    for (const size_t d : task.dependencies) {
      ASSERT_EQ(plan[d].kind, TASK_GRADIENT_TILE);
      EXPECT_EQ(plan[d].params.frame(), task.params.frame());
      const PixelWindow& w = plan[d].params.window();
      EXPECT_LE(w.x1() - w.x0(), 32);
      EXPECT_LE(w.y1() - w.y0(), 32);
      for (int y = w.y0(); y < w.y1(); ++y)
        for (int x = w.x0(); x < w.x1(); ++x) ++covered[static_cast<size_t>(y * 100 + x)];
    }
    EXPECT_EQ(task.dependencies.size(), 12u);
    EXPECT_EQ(std::count(covered.begin(), covered.end(), 1), 100 * 70) << "every pixel in exactly one tile";
  }
  EXPECT_EQ(joins, (std::map<int64_t, int>{{3, 1}, {4, 1}}));

  // A frame of one tile is rendered whole; a frame of more tiles than a join takes gets
  // larger ones.
  spec.set_tile(128);
  for (const PlannedTask& task : planShot(spec)) EXPECT_NE(task.kind, TASK_GRADIENT_TILE);
  spec.set_width(16384);
  spec.set_height(16384);
  spec.set_tile(8);
  spec.set_frame_end(3);
  auto counts = countKinds(planShot(spec));
  EXPECT_EQ(counts[TASK_GRADIENT_TILE], kMaxAssemblyInputs) << "tiles of 256: 64 x 64";
}

TEST(Planner, TgptRendersEveryFrameSolvesWindowsAndBlendsEachFrameFromItsWindows) {
  ShotSpec spec = renderSpec();  // frames 3..4
  spec.set_pipeline(PIPELINE_TGPT);
  spec.set_frame_start(0);
  spec.set_frame_end(11);  // 12 frames, windows of 5 overlapping by 2: [0,5) [3,8) [6,11) [7,12)
  spec.set_poisson_window(5);
  spec.set_poisson_overlap(2);
  spec.set_poisson_norm("l1");
  const auto plan = planShot(spec);
  auto counts = countKinds(plan);
  EXPECT_EQ(counts[TASK_GRADIENT_RENDER], 12);
  EXPECT_EQ(counts[TASK_POISSON_WINDOW], 4);
  EXPECT_EQ(counts[TASK_POISSON_BLEND], 12);
  EXPECT_EQ(counts[TASK_RENDER_TILE], 0);
  std::map<int64_t, std::vector<int64_t>> windowsOf;  // frame -> first frames of the windows blended into it
  for (size_t i = 0; i < plan.size(); ++i) {
    const PlannedTask& task = plan[i];
    EXPECT_EQ(task.output, task.kind == TASK_POISSON_BLEND);
    if (task.kind == TASK_POISSON_WINDOW) {
      std::set<int64_t> frames;
      for (int64_t f = task.params.window_first(); f < task.params.window_first() + task.params.window_frames(); ++f)
        frames.insert(f);
      EXPECT_EQ(dependencyFrames(plan, task, TASK_GRADIENT_RENDER), frames);
    }
    if (task.kind == TASK_POISSON_BLEND) {
      EXPECT_EQ(dependencyFrames(plan, task, TASK_GRADIENT_RENDER), (std::set<int64_t>{task.params.frame()}));
      for (const size_t d : task.dependencies) {
        if (plan[d].kind != TASK_POISSON_WINDOW) continue;
        const TaskParams& window = plan[d].params;
        EXPECT_GE(task.params.frame(), window.window_first());
        EXPECT_LT(task.params.frame(), window.window_first() + window.window_frames());
        windowsOf[task.params.frame()].push_back(window.window_first());
      }
    }
  }
  EXPECT_EQ(windowsOf[0], (std::vector<int64_t>{0}));
  EXPECT_EQ(windowsOf[4], (std::vector<int64_t>{0, 3}));
  EXPECT_EQ(windowsOf[7], (std::vector<int64_t>{3, 6, 7}));  // in window order, as the blend adds them
  EXPECT_EQ(windowsOf[11], (std::vector<int64_t>{7}));

  spec.set_poisson_overlap(5);
  EXPECT_THROW(planShot(spec), PlanError);
  spec.set_poisson_overlap(2);
  spec.set_poisson_norm("l3");
  EXPECT_THROW(planShot(spec), PlanError);
}

ShotSpec metropolisSpec(const std::string& pipeline) {
  ShotSpec spec = renderSpec();
  spec.set_pipeline(*pipelineNamed(pipeline));
  spec.set_frame_start(0);
  spec.set_frame_end(9);  // 10 frames, windows of 4: [0,4) [4,8) [8,10)
  spec.set_mlt_window(4);
  spec.set_mutations_per_pixel(8);
  spec.set_mlt_chains(10);
  spec.set_chains_per_block(3);  // blocks: 4, the last of one chain
  spec.set_chain_tasks(3);       // blocks per task: 2, 1, 1
  spec.set_temporal_delta(0.5);
  spec.set_bootstrap_samples(1000);
  return spec;
}

TEST(Planner, MetropolisPlansAPoolChainBatchesOverEveryBlockAndAMergePerFrame) {
  for (const std::string pipeline : {"pssmlt", "tmlt", "mlt"}) {
    SCOPED_TRACE(pipeline);
    const ShotSpec spec = metropolisSpec(pipeline);
    const auto plan = planShot(spec);
    const int windows = pipeline == "mlt" ? 10 : 3;
    auto counts = countKinds(plan);
    EXPECT_EQ(counts[TASK_MLT_SEED_POOL], windows);
    EXPECT_EQ(counts[TASK_MLT_CHAINS], 3 * windows);
    EXPECT_EQ(counts[TASK_MLT_MERGE], 10);
    std::map<int64_t, std::vector<int>> blocksOfWindow;  // window first frame -> blocks covered, in order
    std::set<int64_t> merged;
    for (const PlannedTask& task : plan) {
      EXPECT_EQ(task.output, task.kind == TASK_MLT_MERGE);
      const TaskParams& p = task.params;
      if (task.kind == TASK_MLT_SEED_POOL) {
        EXPECT_TRUE(task.dependencies.empty());
      }
      if (task.kind == TASK_MLT_CHAINS) {
        ASSERT_EQ(task.dependencies.size(), 1u);
        const PlannedTask& pool = plan[task.dependencies[0]];
        EXPECT_EQ(pool.kind, TASK_MLT_SEED_POOL);
        EXPECT_EQ(pool.params.window_first(), p.window_first());
        EXPECT_EQ(pool.params.window_frames(), p.window_frames());
        for (int b = p.block_first(); b < p.block_first() + p.block_count(); ++b) blocksOfWindow[p.window_first()].push_back(b);
      }
      if (task.kind == TASK_MLT_MERGE) {
        EXPECT_GE(p.frame(), p.window_first());
        EXPECT_LT(p.frame(), p.window_first() + p.window_frames());
        merged.insert(p.frame());
        int pools = 0, batches = 0;
        for (const size_t d : task.dependencies) {
          EXPECT_EQ(plan[d].params.window_first(), p.window_first());
          pools += plan[d].kind == TASK_MLT_SEED_POOL;
          batches += plan[d].kind == TASK_MLT_CHAINS;
        }
        EXPECT_EQ(pools, 1);
        EXPECT_EQ(batches, 3);
      }
    }
    EXPECT_EQ(merged.size(), 10u);
    ASSERT_EQ(blocksOfWindow.size(), static_cast<size_t>(windows));
    for (const auto& [first, blocks] : blocksOfWindow) EXPECT_EQ(blocks, (std::vector<int>{0, 1, 2, 3}));
    EXPECT_EQ(plan.size(), static_cast<size_t>(windows * 4 + 10));  // no evaluation without frames to evaluate
  }
}

TEST(Planner, MetropolisRefusesEmptySettings) {
  ShotSpec spec = metropolisSpec("tmlt");
  spec.set_chain_tasks(100);  // more tasks than blocks: one block each
  auto counts = countKinds(planShot(spec));
  EXPECT_EQ(counts[TASK_MLT_CHAINS], 3 * 4);
  spec.set_temporal_delta(0);
  EXPECT_THROW(planShot(spec), PlanError);
  spec = metropolisSpec("pssmlt");
  spec.set_temporal_delta(0);
  EXPECT_NO_THROW(planShot(spec));  // pssmlt has no temporal perturbation
  spec.set_mlt_chains(0);
  EXPECT_THROW(planShot(spec), PlanError);
  spec = metropolisSpec("pssmlt");
  spec.set_mutations_per_pixel(0);
  EXPECT_THROW(planShot(spec), PlanError);
}

// preview_every: every n-th frame's tasks are planned, and so leased, first; the rest keep
// frame order, and the plan holds the same tasks with the same dependencies.
TEST(Planner, PreviewOrderPlansEveryNthFrameFirst) {
  const auto framesOf = [](const std::vector<PlannedTask>& plan, TaskKind kind) {
    std::vector<int64_t> frames;
    for (const PlannedTask& task : plan)
      if (task.kind == kind) frames.push_back(task.params.frame());
    return frames;
  };
  ShotSpec pt = renderSpec();
  pt.set_frame_start(10);
  pt.set_frame_end(19);
  const auto inOrder = planShot(pt);
  pt.set_preview_every(4);
  const auto preview = planShot(pt);
  EXPECT_EQ(framesOf(inOrder, TASK_ASSEMBLE_FRAME), (std::vector<int64_t>{10, 11, 12, 13, 14, 15, 16, 17, 18, 19}));
  EXPECT_EQ(framesOf(preview, TASK_ASSEMBLE_FRAME), (std::vector<int64_t>{10, 14, 18, 11, 12, 13, 15, 16, 17, 19}));
  EXPECT_EQ(countKinds(preview), countKinds(inOrder));

  ShotSpec d = filteringSpec("d", 1);
  d.set_preview_every(5);
  const auto plan = planShot(d);
  EXPECT_EQ(framesOf(plan, TASK_DENOISE), (std::vector<int64_t>{10, 15, 11, 12, 13, 14, 16, 17, 18, 19}));
  for (const PlannedTask& task : plan) {
    if (task.kind != TASK_DENOISE) continue;
    const int64_t f = task.params.frame();
    std::set<int64_t> neighbours{f};
    if (f > 10) neighbours.insert(f - 1);
    if (f < 19) neighbours.insert(f + 1);
    EXPECT_EQ(dependencyFrames(plan, task, TASK_ASSEMBLE_FRAME), neighbours) << "frame " << f;
  }
}

}  // namespace
}  // namespace pathfarm::farm
