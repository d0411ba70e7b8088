// Messages of bounded size however large the frame: a lease's inputs read in parts, and
// follow-up tiles staged in batches until their task completes.
#include <map>

#include "contract/pipeline.h"
#include "scheduler/farm_state_fixture.h"

namespace pathfarm::farm {
namespace {

using FollowUps = google::protobuf::RepeatedPtrField<TaskParams>;

FollowUps batch(std::initializer_list<TaskParams> tiles) { return FollowUps(tiles.begin(), tiles.end()); }

TEST_F(FarmStateTest, ALeaseWithMoreInputsThanItNamesIsReadInPartsInTaskOrder) {
  // 1500 tiles assembled into one frame: more than a lease names, and more than one part.
  settings_.inlineLeaseInputs = 1000;
  open();
  ShotSpec spec = filteredSpec();
  std::vector<PlannedTask> plan(1500, PlannedTask{TASK_RENDER_TILE, {}, {}});
  PlannedTask assemble{TASK_ASSEMBLE_FRAME, {}, {}, true};
  for (size_t i = 0; i < plan.size(); ++i) {
    plan[i].params.mutable_window()->set_x0(static_cast<int>(i));
    assemble.dependencies.push_back(i);
  }
  plan.push_back(assemble);
  const int64_t shot = state_->submit(spec, plan, now_);
  const int64_t worker = state_->registerWorker("w", 1, now_);
  for (int i = 0; i < 1500; ++i) {
    const Lease tile = leaseFor(worker);
    ASSERT_TRUE(complete(tile.attempt_id(), storedChunk("t" + std::to_string(i)), now_).accepted());
  }
  const Lease lease = leaseFor(worker);
  ASSERT_EQ(lease.kind(), TASK_ASSEMBLE_FRAME);
  EXPECT_TRUE(lease.inputs_streamed());
  EXPECT_EQ(lease.inputs_size(), 0);

  std::vector<int> windows;
  int64_t after = 0;
  int parts = 0;
  for (;;) {
    const auto part = state_->leaseInputs(lease.attempt_id(), after);
    ASSERT_TRUE(part.has_value());
    if (part->lastTaskId == 0) break;
    ++parts;
    ASSERT_LE(part->part.inputs_size(), FarmState::kInputsPerPart);
    ASSERT_EQ(part->part.input_params_size(), part->part.inputs_size());
    ASSERT_EQ(part->part.input_kinds_size(), part->part.inputs_size());
    for (const TaskParams& params : part->part.input_params()) windows.push_back(params.window().x0());
    after = part->lastTaskId;
  }
  EXPECT_EQ(parts, 2);
  ASSERT_EQ(windows.size(), 1500u);
  for (int i = 0; i < 1500; ++i) ASSERT_EQ(windows[static_cast<size_t>(i)], i) << "inputs out of task order";

  // Only the running attempt reads them.
  ASSERT_TRUE(complete(lease.attempt_id(), storedChunk("frame"), now_).accepted());
  EXPECT_FALSE(state_->leaseInputs(lease.attempt_id(), 0).has_value());
  EXPECT_EQ(state_->summary(shot, now_).state(), SHOT_DONE);
}

TEST_F(FarmStateTest, ALeaseWithFewInputsNamesThemAll) {
  submitFrame();
  const int64_t worker = state_->registerWorker("w", 1, now_);
  for (int i = 0; i < 2; ++i) complete(leaseFor(worker).attempt_id(), storedChunk("t" + std::to_string(i)), now_);
  const Lease assemble = leaseFor(worker);
  ASSERT_EQ(assemble.kind(), TASK_ASSEMBLE_FRAME);
  EXPECT_FALSE(assemble.inputs_streamed());
  EXPECT_EQ(assemble.inputs_size(), 2);
}

TEST_F(FarmStateTest, FollowUpsStagedInBatchesJoinTheShotAtCompletion) {
  const int64_t shot = submitFiltered();
  const int64_t worker = state_->registerWorker("w", 1, now_);
  const Lease interpolate = leaseFor(worker);
  const FollowUps first = batch({rerenderTile(0, 0)}), second = batch({rerenderTile(8, 0)});
  ASSERT_TRUE(state_->stageFollowUps(interpolate.attempt_id(), first).accepted());
  ASSERT_TRUE(state_->stageFollowUps(interpolate.attempt_id(), second).accepted());
  EXPECT_EQ(state_->summary(shot, now_).tasks_total(), 2) << "staged tiles are no tasks yet";
  EXPECT_FALSE(state_->lease(worker, now_).has_value());
  ASSERT_TRUE(complete(interpolate.attempt_id(), storedChunk("i"), now_).accepted());
  EXPECT_EQ(state_->summary(shot, now_).tasks_total(), 4);
  const Lease tile = leaseFor(worker);
  EXPECT_EQ(tile.kind(), TASK_RENDER_TILE);
  EXPECT_EQ(tile.params().window().x0(), 0);
}

TEST_F(FarmStateTest, FollowUpsOfAnAttemptThatDoesNotCompleteAreDropped) {
  const int64_t shot = submitFiltered();
  const int64_t worker = state_->registerWorker("w", 1, now_);
  const Lease failing = leaseFor(worker);
  ASSERT_TRUE(state_->stageFollowUps(failing.attempt_id(), batch({rerenderTile(0, 0)})).accepted());
  ASSERT_TRUE(state_->fail(failing.attempt_id(), "crashed", now_).accepted());
  EXPECT_FALSE(state_->stageFollowUps(failing.attempt_id(), batch({rerenderTile(8, 0)})).accepted());

  now_ += 100;  // past the retry backoff
  const Lease expiring = leaseFor(worker);
  ASSERT_EQ(expiring.task_id(), failing.task_id());
  ASSERT_TRUE(state_->stageFollowUps(expiring.attempt_id(), batch({rerenderTile(8, 0)})).accepted());
  now_ += 100;
  ASSERT_EQ(state_->expireLeases(now_), 1);

  now_ += 100;
  const Lease completing = leaseFor(worker);
  ASSERT_EQ(completing.task_id(), failing.task_id());
  ASSERT_TRUE(complete(completing.attempt_id(), storedChunk("i"), now_).accepted());
  EXPECT_EQ(state_->summary(shot, now_).tasks_total(), 2) << "a tile staged by an attempt that ended joined the shot";
  EXPECT_EQ(leaseFor(worker).kind(), TASK_COMPOSITE);
}

// A composite of a window of rows waits for the re-render tiles within kCompositeHalo of
// its rows, not for the others; the frame's composite, joining the windows, for none.
TEST_F(FarmStateTest, FollowUpsJoinTheWindowsCompositesWhoseHaloTheyReach) {
  ShotSpec spec = filteredSpec();
  spec.set_height(200);
  std::vector<PlannedTask> plan = {{TASK_INTERPOLATE, {}, {}}};
  for (const auto& [first, end] : {std::pair{0, 100}, {100, 200}}) {
    PlannedTask window{TASK_COMPOSITE, {}, {0}};
    window.params.mutable_window()->set_y0(first);
    window.params.mutable_window()->set_y1(end);
    window.params.mutable_window()->set_x1(16);
    plan.push_back(window);
  }
  plan.push_back({TASK_COMPOSITE, {}, {1, 2}, true});
  state_->submit(spec, plan, now_);
  const int64_t worker = state_->registerWorker("w", 1, now_);
  const Lease interpolate = leaseFor(worker);
  static_assert(kCompositeHalo == 32, "the tiles below are placed for a halo of 32 rows");
  // Rows 0-8 reach the first window alone, 64-72 both (72 > 100 - 32), 192-200 the second.
  ASSERT_TRUE(state_->stageFollowUps(interpolate.attempt_id(),
                                     batch({rerenderTile(0, 0), rerenderTile(0, 64), rerenderTile(8, 192)}))
                  .accepted());
  ASSERT_TRUE(complete(interpolate.attempt_id(), storedChunk("i"), now_).accepted());
  // The three tiles and the two windows, in whichever order they become ready.
  std::map<int, std::vector<int>> tilesOf;  // a window's first row -> its tiles' first rows
  for (int i = 0; i < 5; ++i) {
    const Lease lease = leaseFor(worker);
    ASSERT_TRUE(lease.kind() == TASK_RENDER_TILE || lease.params().has_window()) << "the join came before a window";
    for (int input = 0; input < lease.inputs_size(); ++input)
      if (lease.input_kinds(input) == TASK_RENDER_TILE)
        tilesOf[lease.params().window().y0()].push_back(lease.input_params(input).window().y0());
    ASSERT_TRUE(complete(lease.attempt_id(), storedChunk("c" + std::to_string(i)), now_).accepted());
  }
  EXPECT_EQ(tilesOf[0], (std::vector<int>{0, 64}));
  EXPECT_EQ(tilesOf[100], (std::vector<int>{64, 192}));
  const Lease joined = leaseFor(worker);
  ASSERT_EQ(joined.kind(), TASK_COMPOSITE);
  EXPECT_EQ(joined.inputs_size(), 2) << "the frame's composite reads its windows' composites alone";
}

TEST_F(FarmStateTest, FollowUpsThatAreNoTilesOfTheFrameAreRefused) {
  submitFiltered();
  const int64_t worker = state_->registerWorker("w", 1, now_);
  const Lease interpolate = leaseFor(worker);
  const auto refusal = [&](const TaskParams& tile) {
    const ReportReply reply = state_->stageFollowUps(interpolate.attempt_id(), batch({tile}));
    EXPECT_FALSE(reply.accepted());
    return reply.reason();
  };
  TaskParams outside = rerenderTile(16, 0);
  EXPECT_NE(refusal(outside).find("not inside the frame"), std::string::npos);
  TaskParams large = rerenderTile(0, 0);
  large.mutable_window()->set_x1(16);
  EXPECT_NE(refusal(large).find("larger than the shot's tiles"), std::string::npos);
  TaskParams masked = rerenderTile(0, 0);
  masked.set_pixel_mask(std::string(63, '\1'));
  EXPECT_NE(refusal(masked).find("pixel mask"), std::string::npos);
  TaskParams keyframe = rerenderTile(0, 0);
  keyframe.set_role(ROLE_KEYFRAME);
  EXPECT_NE(refusal(keyframe).find("not a re-render"), std::string::npos);
  TaskParams otherFrame = rerenderTile(0, 0);
  otherFrame.set_frame(1);
  EXPECT_NE(refusal(otherFrame).find("not of the task's frame"), std::string::npos);
  TaskParams moreSamples = rerenderTile(0, 0);
  moreSamples.set_spp(1000);
  EXPECT_NE(refusal(moreSamples).find("asks for 1000 samples, not the shot's re-render's 4"), std::string::npos);
  TaskParams fewerSamples = rerenderTile(0, 0);  // a worker may not cheapen the re-render either
  fewerSamples.set_spp(1);
  EXPECT_NE(refusal(fewerSamples).find("asks for 1 samples"), std::string::npos);

  // The frame holds two tiles: a third is more than any filter can ask for.
  const FollowUps three = batch({rerenderTile(0, 0), rerenderTile(8, 0), rerenderTile(0, 0)});
  EXPECT_NE(state_->stageFollowUps(interpolate.attempt_id(), three).reason().find("more follow-up tiles"),
            std::string::npos);
  EXPECT_TRUE(state_->stageFollowUps(interpolate.attempt_id(), batch({rerenderTile(0, 0), rerenderTile(8, 0)})).accepted());
  EXPECT_FALSE(state_->stageFollowUps(interpolate.attempt_id(), batch({rerenderTile(8, 0)})).accepted());
}

}  // namespace
}  // namespace pathfarm::farm
