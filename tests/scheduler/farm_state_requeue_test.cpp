// Requeueing a task or a frame: what ran runs again with everything downstream of it,
// follow-up tiles are asked for afresh, running attempts are revoked, a done shot runs
// again, and what cannot be requeued is refused.
#include "scheduler/farm_state_fixture.h"

namespace pathfarm::farm {
namespace {

class RequeueTest : public FarmStateTest {
 protected:
  // Runs every ready task of the only worker to completion, each with its own chunk.
  void runEverything(int64_t worker) {
    for (int n = 0; auto lease = state_->lease(worker, now_); ++n)
      ASSERT_TRUE(complete(lease->attempt_id(), storedChunk("out" + std::to_string(n) + "_" +
                                                             std::to_string(lease->attempt_id())),
                           now_)
                      .accepted());
  }
};

TEST_F(RequeueTest, ADoneFrameRunsAgainAndTheShotEndsAgain) {
  const int64_t shot = submitFrame();
  const int64_t worker = state_->registerWorker("w", 1, now_);
  runEverything(worker);
  ASSERT_EQ(state_->summary(shot, now_).state(), SHOT_DONE);
  const std::string firstFrame = state_->outputs(shot).at(0).second.sha256();

  const ShotSummary requeued = state_->requeueFrame(shot, 0, now_);
  EXPECT_EQ(requeued.state(), SHOT_RUNNING);
  EXPECT_EQ(requeued.tasks_done(), 0);
  EXPECT_EQ(requeued.tasks_total(), 3);
  EXPECT_TRUE(state_->outputs(shot).empty()) << "a requeued frame is not an output until it is done again";
  const Lease a = leaseFor(worker), b = leaseFor(worker);
  EXPECT_EQ(a.kind(), TASK_RENDER_TILE);
  EXPECT_EQ(b.kind(), TASK_RENDER_TILE);
  EXPECT_FALSE(state_->lease(worker, now_).has_value()) << "the assembly must wait for its tiles again";
  ASSERT_TRUE(complete(a.attempt_id(), storedChunk("a2"), now_).accepted());
  ASSERT_TRUE(complete(b.attempt_id(), storedChunk("b2"), now_).accepted());
  const Lease assemble = leaseFor(worker);
  ASSERT_EQ(assemble.kind(), TASK_ASSEMBLE_FRAME);
  EXPECT_EQ(assemble.inputs(0).sha256(), storedChunk("a2").sha256());
  ASSERT_TRUE(complete(assemble.attempt_id(), storedChunk("frame2"), now_).accepted());
  EXPECT_EQ(state_->summary(shot, now_).state(), SHOT_DONE);
  ASSERT_EQ(state_->outputs(shot).size(), 1u);
  EXPECT_NE(state_->outputs(shot)[0].second.sha256(), firstFrame);
  EXPECT_EQ(state_->outputs(shot)[0].second.sha256(), storedChunk("frame2").sha256());
}

TEST_F(RequeueTest, ATaskRunsAgainWithWhatUsedItAndNothingElse) {
  const int64_t shot = submitFrame();
  const int64_t worker = state_->registerWorker("w", 1, now_);
  const Lease first = leaseFor(worker);
  ASSERT_TRUE(complete(first.attempt_id(), storedChunk("left"), now_).accepted());
  runEverything(worker);
  ASSERT_EQ(state_->summary(shot, now_).state(), SHOT_DONE);

  const ShotSummary requeued = state_->requeueTask(shot, first.task_id(), now_);
  EXPECT_EQ(requeued.tasks_done(), 1) << "the other tile stays done";
  const Lease again = leaseFor(worker);
  EXPECT_EQ(again.task_id(), first.task_id());
  EXPECT_FALSE(state_->lease(worker, now_).has_value());
  ASSERT_TRUE(complete(again.attempt_id(), storedChunk("left2"), now_).accepted());
  const Lease assemble = leaseFor(worker);
  ASSERT_EQ(assemble.kind(), TASK_ASSEMBLE_FRAME);
  ASSERT_TRUE(complete(assemble.attempt_id(), storedChunk("frame2"), now_).accepted());
  EXPECT_EQ(state_->summary(shot, now_).state(), SHOT_DONE);
}

TEST_F(RequeueTest, ARunningAttemptIsRevoked) {
  const int64_t shot = submitFrame();
  const int64_t worker = state_->registerWorker("w", 2, now_);
  const Lease running = leaseFor(worker);
  state_->requeueTask(shot, running.task_id(), now_);
  EXPECT_FALSE(state_->heartbeat(running.attempt_id(), 0.5, now_).keep_going());
  EXPECT_FALSE(complete(running.attempt_id(), storedChunk("late"), now_).accepted());
  bool leasedAgain = false;
  while (auto lease = state_->lease(worker, now_)) leasedAgain |= lease->task_id() == running.task_id();
  EXPECT_TRUE(leasedAgain);
  EXPECT_EQ(state_->summary(shot, now_).state(), SHOT_RUNNING);
}

TEST_F(RequeueTest, FollowUpTilesAreAskedForAfresh) {
  const int64_t shot = submitFiltered();
  const int64_t worker = state_->registerWorker("w", 1, now_);
  const std::vector<TaskParams> tiles = {rerenderTile(0, 0), rerenderTile(8, 0)};
  const Lease interpolate = leaseFor(worker);
  ASSERT_TRUE(complete(interpolate.attempt_id(), storedChunk("i"), now_, tiles).accepted());
  runEverything(worker);
  ASSERT_EQ(state_->summary(shot, now_).state(), SHOT_DONE);
  ASSERT_EQ(state_->summary(shot, now_).tasks_total(), 4);

  // The interpolation runs again and asks for one tile this time: the composite waits for
  // that one only, and the two old tiles are gone.
  const ShotSummary requeued = state_->requeueTask(shot, interpolate.task_id(), now_);
  EXPECT_EQ(requeued.tasks_total(), 2);
  EXPECT_EQ(requeued.tasks_done(), 0);
  const Lease again = leaseFor(worker);
  ASSERT_EQ(again.kind(), TASK_INTERPOLATE);
  EXPECT_FALSE(state_->lease(worker, now_).has_value());
  ASSERT_TRUE(complete(again.attempt_id(), storedChunk("i2"), now_, {tiles[1]}).accepted());
  const Lease tile = leaseFor(worker);
  ASSERT_EQ(tile.kind(), TASK_RENDER_TILE);
  EXPECT_EQ(tile.params().window().x0(), 8);
  ASSERT_TRUE(complete(tile.attempt_id(), storedChunk("t2"), now_).accepted());
  const Lease composite = leaseFor(worker);
  ASSERT_EQ(composite.kind(), TASK_COMPOSITE);
  ASSERT_EQ(composite.inputs_size(), 2);
  EXPECT_EQ(composite.inputs(0).sha256(), storedChunk("i2").sha256());
  EXPECT_EQ(composite.inputs(1).sha256(), storedChunk("t2").sha256());
  ASSERT_TRUE(complete(composite.attempt_id(), storedChunk("c2"), now_).accepted());
  EXPECT_EQ(state_->summary(shot, now_).state(), SHOT_DONE);
  EXPECT_EQ(state_->summary(shot, now_).tasks_total(), 3);
}

TEST_F(RequeueTest, WhatCannotRunAgainIsRefused) {
  const int64_t shot = submitFrame(0, 1);  // fails at its first failure
  const int64_t other = submitFrame();
  const int64_t worker = state_->registerWorker("w", 1, now_);
  const Lease lease = leaseFor(worker);
  ASSERT_EQ(lease.shot_id(), shot);
  // A task or frame the shot does not have is not found (NOT_FOUND, 404); one that cannot
  // run again now is refused (FAILED_PRECONDITION, 409).
  EXPECT_THROW(state_->requeueTask(other, lease.task_id(), now_), std::out_of_range) << "a task of another shot";
  EXPECT_THROW(state_->requeueTask(shot, 9999, now_), std::out_of_range);
  EXPECT_THROW(state_->requeueFrame(shot, 7, now_), std::out_of_range) << "the shot has only frame 0";
  EXPECT_THROW(state_->requeueFrame(shot + 100, 0, now_), std::out_of_range);
  state_->cancel(other, now_);
  EXPECT_THROW(state_->requeueFrame(other, 0, now_), std::invalid_argument);
  ASSERT_TRUE(state_->fail(lease.attempt_id(), "bad scene", now_).accepted());
  ASSERT_EQ(state_->summary(shot, now_).state(), SHOT_FAILED);
  EXPECT_THROW(state_->requeueFrame(shot, 0, now_), std::invalid_argument) << "a failed shot is retried first";
}

}  // namespace
}  // namespace pathfarm::farm
