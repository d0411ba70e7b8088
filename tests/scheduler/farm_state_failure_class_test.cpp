// Whose fault a failure is decides what the farm does with it: a bad input, once two
// workers report it, fails the task and its shot and blames nobody; a transfer failure
// runs the task again without blaming the worker; a worker fault counts toward that
// worker's blocklist.
#include "scheduler/farm_state_fixture.h"

namespace pathfarm::farm {
namespace {

TEST_F(FarmStateTest, ABadInputTwoWorkersReportFailsTheShotAndBlamesNoWorker) {
  const int64_t shot = submitFrame(0, 10);
  const int64_t first = state_->registerWorker("first", 1, now_), second = state_->registerWorker("second", 1, now_);
  const std::string reason = "scene.json: \"radius\": not a finite number";
  const Lease lease = leaseFor(first);
  ASSERT_TRUE(state_->fail(lease.attempt_id(), reason, now_, "", FAILURE_BAD_INPUT).accepted());
  EXPECT_EQ(state_->summary(shot, now_).state(), SHOT_RUNNING) << "one worker's word failed the shot";
  now_ += settings_.retryBackoffSeconds;
  const Lease again = leaseFor(second);
  ASSERT_EQ(again.task_id(), lease.task_id());
  ASSERT_TRUE(state_->fail(again.attempt_id(), reason, now_, "", FAILURE_BAD_INPUT).accepted());
  const ShotSummary summary = state_->summary(shot, now_);
  EXPECT_EQ(summary.state(), SHOT_FAILED) << "a bad input was retried although no worker can run it";
  EXPECT_NE(summary.failure().find("bad input"), std::string::npos) << summary.failure();
  EXPECT_NE(summary.failure().find("\"radius\""), std::string::npos) << summary.failure();
  EXPECT_TRUE(state_->blocklist(shot).empty());
  const FarmMetrics metrics = state_->metrics(now_);
  EXPECT_EQ(metrics.attemptsEnded.at("bad_input"), 2);
  EXPECT_EQ(metrics.attemptsEnded.at("worker_fault"), 0);
}

TEST_F(FarmStateTest, OneWorkerAloneCannotFailAShotAsBadInput) {
  const int64_t shot = submitFrame(0, 10);
  const int64_t liar = state_->registerWorker("liar", 1, now_);
  for (int report = 0; report < 3; ++report) {
    const Lease lease = leaseFor(liar);
    ASSERT_TRUE(state_->fail(lease.attempt_id(), "bad input, it says", now_, "", FAILURE_BAD_INPUT).accepted());
    now_ += 100;  // past any backoff
  }
  EXPECT_EQ(state_->summary(shot, now_).state(), SHOT_RUNNING);
  EXPECT_TRUE(state_->blocklist(shot).empty());
}

TEST_F(FarmStateTest, ATransferFailureRunsTheTaskAgainAndBlamesNoWorker) {
  const int64_t shot = submitFrame(0, 3);
  const int64_t only = state_->registerWorker("only", 1, now_);
  const Lease first = leaseFor(only), second = leaseFor(only);
  // As many as would blocklist the worker (blocklistAfter is 2) had they been its fault.
  for (const Lease& lease : {first, second})
    ASSERT_TRUE(state_->fail(lease.attempt_id(), "cannot upload its output: the store's disk is full", now_, "",
                             FAILURE_TRANSPORT)
                    .accepted());
  EXPECT_TRUE(state_->blocklist(shot).empty());
  now_ += settings_.retryBackoffSeconds;
  EXPECT_EQ(leaseFor(only).task_id(), first.task_id()) << "the only worker may run the task again";
  EXPECT_EQ(state_->summary(shot, now_).state(), SHOT_RUNNING);
  EXPECT_EQ(state_->metrics(now_).attemptsEnded.at("transport"), 2);
}

// A task handed back by a stopping worker (a preempted node) runs again, counted as a
// lost worker: no attempt charged, no worker blamed, and bounded by --max-lost-workers as
// a vanishing worker is.
TEST_F(FarmStateTest, ATaskHandedBackIsCountedAsALostWorkerNotAsAFailure) {
  const int64_t shot = submitFrame(0, 1);
  const int64_t leaving = state_->registerWorker("leaving", 1, now_);
  for (int release = 1; release < settings_.maxLostWorkers; ++release) {
    const Lease lease = leaseFor(leaving);
    ASSERT_TRUE(
        state_->fail(lease.attempt_id(), "its worker was told to stop", now_, "", FAILURE_RELEASED).accepted());
    EXPECT_EQ(state_->summary(shot, now_).state(), SHOT_RUNNING) << "after " << release << " releases";
    now_ += settings_.retryBackoffSeconds;
  }
  EXPECT_TRUE(state_->blocklist(shot).empty());
  EXPECT_EQ(state_->metrics(now_).attemptsEnded.at("released"), settings_.maxLostWorkers - 1);
  EXPECT_EQ(state_->metrics(now_).attemptsEnded.at("worker_fault"), 0);
  const Lease last = leaseFor(leaving);
  ASSERT_TRUE(state_->fail(last.attempt_id(), "its worker was told to stop", now_, "", FAILURE_RELEASED).accepted());
  const ShotSummary summary = state_->summary(shot, now_);
  EXPECT_EQ(summary.state(), SHOT_FAILED);
  EXPECT_NE(summary.failure().find("lost its worker"), std::string::npos) << summary.failure();
}

TEST_F(FarmStateTest, TransferFailuresStillCountTowardTheTasksAttempts) {
  const int64_t shot = submitFrame(0, 2);
  const int64_t worker = state_->registerWorker("w", 1, now_);
  const Lease first = leaseFor(worker);
  ASSERT_TRUE(state_->fail(first.attempt_id(), "cannot fetch input chunk", now_, "", FAILURE_TRANSPORT).accepted());
  leaseFor(worker);  // the other tile
  now_ += settings_.retryBackoffSeconds;
  const Lease retry = leaseFor(worker);
  ASSERT_EQ(retry.task_id(), first.task_id());
  ASSERT_TRUE(state_->fail(retry.attempt_id(), "cannot fetch input chunk", now_, "", FAILURE_TRANSPORT).accepted());
  const ShotSummary summary = state_->summary(shot, now_);
  EXPECT_EQ(summary.state(), SHOT_FAILED);
  EXPECT_NE(summary.failure().find("failed 2 times"), std::string::npos) << summary.failure();
}

TEST_F(FarmStateTest, AnUnknownFailureClassIsTheWorkersFault) {
  const int64_t shot = submitFrame(0, 10);
  const int64_t worker = state_->registerWorker("w", 1, now_);
  state_->registerWorker("other", 1, now_);
  const Lease first = leaseFor(worker), second = leaseFor(worker);
  for (const Lease& lease : {first, second})
    ASSERT_TRUE(state_->fail(lease.attempt_id(), "a class from a newer worker", now_, "", static_cast<FailureClass>(7))
                    .accepted());
  EXPECT_EQ(state_->blocklist(shot).size(), 1u);
  EXPECT_EQ(state_->metrics(now_).attemptsEnded.at("worker_fault"), 2);
}

}  // namespace
}  // namespace pathfarm::farm
