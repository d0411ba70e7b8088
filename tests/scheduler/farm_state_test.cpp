// The farm's state machine with a controlled clock: leasing rules, stale reports,
// expiry, retries, blocklists, hung tasks, shot control, and a restart.
#include <cmath>
#include <functional>
#include <limits>
#include <map>

#include "scheduler/farm_state_fixture.h"
#include "scheduler/schema.h"
#include "test_support.h"

namespace pathfarm::farm {
namespace {

TEST_F(FarmStateTest, AssemblyWaitsForItsTilesAndGetsTheirChunks) {
  const int64_t shot = submitFrame();
  const int64_t worker = state_->registerWorker("w", 1, now_);
  const Lease a = leaseFor(worker), b = leaseFor(worker);
  EXPECT_EQ(a.kind(), TASK_RENDER_TILE);
  EXPECT_EQ(b.kind(), TASK_RENDER_TILE);
  EXPECT_FALSE(state_->lease(worker, now_).has_value()) << "assembly leased before its tiles were done";
  EXPECT_TRUE(complete(a.attempt_id(), storedChunk("a"), now_).accepted());
  EXPECT_FALSE(state_->lease(worker, now_).has_value());
  EXPECT_TRUE(complete(b.attempt_id(), storedChunk("b"), now_).accepted());
  const Lease assemble = leaseFor(worker);
  ASSERT_EQ(assemble.kind(), TASK_ASSEMBLE_FRAME);
  ASSERT_EQ(assemble.inputs_size(), 2);
  EXPECT_EQ(assemble.inputs(0).sha256(), storedChunk("a").sha256());
  EXPECT_EQ(assemble.input_params(1).window().x0(), 32);
  EXPECT_EQ(state_->summary(shot, now_).state(), SHOT_RUNNING);
  EXPECT_TRUE(complete(assemble.attempt_id(), storedChunk("frame"), now_).accepted());
  const ShotSummary done = state_->summary(shot, now_);
  EXPECT_EQ(done.state(), SHOT_DONE);
  EXPECT_EQ(done.tasks_done(), 3);
  EXPECT_EQ(done.frames_done(), 1);
  ASSERT_EQ(state_->outputs(shot).size(), 1u);
  EXPECT_EQ(state_->outputs(shot)[0].second.sha256(), storedChunk("frame").sha256());
}

// A shot waiting for another is not leased until that one is done, whatever its priority.
TEST_F(FarmStateTest, AShotWaitsUntilTheShotsItNamesAreDone) {
  const int64_t first = submitFrame();
  const int64_t second = submitFrame(5, 3, {first});
  const int64_t worker = state_->registerWorker("w", 1, now_);
  const Lease a = leaseFor(worker), b = leaseFor(worker);
  EXPECT_EQ(a.shot_id(), first);
  EXPECT_EQ(b.shot_id(), first);
  EXPECT_FALSE(state_->lease(worker, now_).has_value()) << "the waiting shot was leased";
  EXPECT_TRUE(complete(a.attempt_id(), storedChunk("a"), now_).accepted());
  EXPECT_TRUE(complete(b.attempt_id(), storedChunk("b"), now_).accepted());
  const Lease assemble = leaseFor(worker);
  EXPECT_EQ(assemble.shot_id(), first);
  EXPECT_TRUE(complete(assemble.attempt_id(), storedChunk("frame"), now_).accepted());
  EXPECT_EQ(state_->summary(first, now_).state(), SHOT_DONE);
  EXPECT_EQ(leaseFor(worker).shot_id(), second);
}

// One that ends failed or cancelled fails the shots waiting for it, and theirs in turn; a
// shot cannot wait for one that does not exist or can no longer be done.
TEST_F(FarmStateTest, AShotFailsWithTheShotItWaitsFor) {
  const int64_t first = submitFrame();
  const int64_t second = submitFrame(0, 3, {first});
  const int64_t third = submitFrame(0, 3, {second});
  const int64_t unrelated = submitFrame();
  state_->cancel(first, now_);
  const ShotSummary failed = state_->summary(second, now_);
  EXPECT_EQ(failed.state(), SHOT_FAILED);
  EXPECT_NE(failed.failure().find("shot " + std::to_string(first) + ", which it waits for, ended SHOT_CANCELLED"),
            std::string::npos)
      << failed.failure();
  EXPECT_EQ(state_->summary(third, now_).state(), SHOT_FAILED);
  EXPECT_EQ(state_->summary(unrelated, now_).state(), SHOT_QUEUED);
  EXPECT_THROW(submitFrame(0, 3, {first}), std::invalid_argument);
  EXPECT_THROW(submitFrame(0, 3, {unrelated + 100}), std::invalid_argument);
}

TEST_F(FarmStateTest, CompletionNeedsItsChunkStoredFirst) {
  submitFrame();
  const Lease lease = leaseFor(state_->registerWorker("w", 1, now_));
  ChunkRef missing;
  missing.set_sha256(std::string(64, 'f'));
  EXPECT_FALSE(complete(lease.attempt_id(), missing, now_).accepted());
  EXPECT_TRUE(complete(lease.attempt_id(), storedChunk("x"), now_).accepted());
}

TEST_F(FarmStateTest, PriorityThenAgeDecideWhoGoesFirst) {
  const int64_t older = submitFrame(0);
  const int64_t urgent = submitFrame(5);
  const int64_t newer = submitFrame(0);
  const int64_t worker = state_->registerWorker("w", 1, now_);
  EXPECT_EQ(leaseFor(worker).shot_id(), urgent);
  EXPECT_EQ(leaseFor(worker).shot_id(), urgent);
  EXPECT_EQ(leaseFor(worker).shot_id(), older);  // urgent's assembly is not ready
  state_->pause(older, now_);
  EXPECT_EQ(leaseFor(worker).shot_id(), newer);
  state_->resume(older, now_);
  EXPECT_EQ(leaseFor(worker).shot_id(), older);
}

TEST_F(FarmStateTest, ExpiredLeaseIsRequeuedAndItsLateReportsRefused) {
  const int64_t shot = submitFrame();
  const int64_t w1 = state_->registerWorker("w1", 1, now_), w2 = state_->registerWorker("w2", 1, now_);
  const Lease first = leaseFor(w1);
  now_ += 5;
  EXPECT_TRUE(state_->heartbeat(first.attempt_id(), 0.5, now_).keep_going());  // renewed to now + 10
  now_ += 9;
  EXPECT_EQ(state_->expireLeases(now_), 0);
  now_ += 2;
  EXPECT_EQ(state_->expireLeases(now_), 1);
  // The task comes back after its retry backoff, under a new attempt id.
  EXPECT_NE(leaseFor(w2).task_id(), first.task_id());
  EXPECT_FALSE(state_->lease(w2, now_).has_value());
  now_ += settings_.retryBackoffSeconds;
  const Lease second = leaseFor(w2);
  EXPECT_EQ(second.task_id(), first.task_id());
  EXPECT_NE(second.attempt_id(), first.attempt_id());
  // The first worker comes back late: nothing it says changes anything.
  EXPECT_FALSE(state_->heartbeat(first.attempt_id(), 1.0, now_).keep_going());
  EXPECT_FALSE(complete(first.attempt_id(), storedChunk("late"), now_).accepted());
  EXPECT_FALSE(state_->fail(first.attempt_id(), "late", now_).accepted());
  EXPECT_TRUE(complete(second.attempt_id(), storedChunk("good"), now_).accepted());
  EXPECT_EQ(state_->summary(shot, now_).attempts(), 3);
}

TEST_F(FarmStateTest, ALostWorkerIsNotChargedToTheTasksAttempts) {
  const int64_t shot = submitFrame(0, 2);  // two failures would fail it
  const int64_t worker = state_->registerWorker("w", 1, now_);
  const Lease other = leaseFor(worker);
  ASSERT_TRUE(complete(other.attempt_id(), storedChunk("other tile"), now_).accepted());
  int64_t task = 0;
  for (int loss = 1; loss < settings_.maxLostWorkers; ++loss) {
    const Lease lease = leaseFor(worker);
    if (task) {
      EXPECT_EQ(lease.task_id(), task);
    }
    task = lease.task_id();
    now_ += settings_.leaseSeconds + 1;  // the worker vanished: no heartbeat
    ASSERT_EQ(state_->expireLeases(now_), 1);
    EXPECT_EQ(state_->summary(shot, now_).state(), SHOT_RUNNING) << "after " << loss << " losses";
    now_ += settings_.retryBackoffSeconds;
  }
  const Lease last = leaseFor(worker);
  EXPECT_EQ(last.task_id(), task);
  ASSERT_TRUE(complete(last.attempt_id(), storedChunk("tile"), now_).accepted());
  EXPECT_EQ(leaseFor(worker).kind(), TASK_ASSEMBLE_FRAME);
}

TEST_F(FarmStateTest, ATaskThatLosesEveryWorkerFailsTheShotInTheEnd) {
  const int64_t shot = submitFrame(0, 2);
  const int64_t worker = state_->registerWorker("w", 1, now_);
  ASSERT_TRUE(complete(leaseFor(worker).attempt_id(), storedChunk("other tile"), now_).accepted());
  for (int loss = 0; loss < settings_.maxLostWorkers; ++loss) {
    ASSERT_EQ(state_->summary(shot, now_).state(), SHOT_RUNNING) << "after " << loss << " losses";
    leaseFor(worker);
    now_ += settings_.leaseSeconds + 1;
    ASSERT_EQ(state_->expireLeases(now_), 1);
    now_ += settings_.retryBackoffSeconds;
  }
  const ShotSummary summary = state_->summary(shot, now_);
  EXPECT_EQ(summary.state(), SHOT_FAILED);
  EXPECT_NE(summary.failure().find("lost its worker 10 times"), std::string::npos) << summary.failure();
  EXPECT_NE(summary.failure().find("the lease expired"), std::string::npos) << summary.failure();
}

TEST_F(FarmStateTest, AnAttemptKeepsTheTailOfItsWorkersLogAndNoMore) {
  const int64_t shot = submitFrame(0, 2);
  const int64_t worker = state_->registerWorker("w", 1, now_);
  const Lease failed = leaseFor(worker);
  // A worker sends more than the farm keeps: the end of it stays.
  const std::string flood = std::string(FarmState::kMaxLogTailBytes, 'x') + "the last line\n";
  ASSERT_TRUE(state_->fail(failed.attempt_id(), "out of memory", now_, flood).accepted());
  const Lease done = leaseFor(worker);
  CompleteRequest request;
  request.set_attempt_id(done.attempt_id());
  *request.mutable_output() = storedChunk("a tile");
  request.set_log_tail("task started\ntask done\n");
  ASSERT_TRUE(state_->complete(request, now_).accepted());
  std::map<int64_t, std::string> tails;
  for (const auto& task : state_->taskDetails(shot, std::nullopt, 0, 10).tasks)
    for (const auto& attempt : task.attempts) tails[attempt.id] = attempt.logTail;
  ASSERT_EQ(tails.at(failed.attempt_id()).size(), FarmState::kMaxLogTailBytes);
  EXPECT_EQ(tails.at(failed.attempt_id()).substr(FarmState::kMaxLogTailBytes - 14), "the last line\n");
  EXPECT_EQ(tails.at(done.attempt_id()), "task started\ntask done\n");
}

TEST_F(FarmStateTest, FailuresBackOffThenFailTheShotWithTheReason) {
  const int64_t shot = submitFrame(0, 2);
  const int64_t worker = state_->registerWorker("w", 1, now_);
  const Lease first = leaseFor(worker);
  EXPECT_TRUE(state_->fail(first.attempt_id(), "scene.json: cannot open the scene file", now_).accepted());
  leaseFor(worker);  // the other tile
  EXPECT_FALSE(state_->lease(worker, now_).has_value()) << "retried before its backoff";
  now_ += settings_.retryBackoffSeconds;
  const Lease retry = leaseFor(worker);
  EXPECT_EQ(retry.task_id(), first.task_id());
  EXPECT_TRUE(state_->fail(retry.attempt_id(), "scene.json: cannot open the scene file", now_).accepted());
  const ShotSummary summary = state_->summary(shot, now_);
  EXPECT_EQ(summary.state(), SHOT_FAILED);
  EXPECT_NE(summary.failure().find("failed 2 times"), std::string::npos) << summary.failure();
  EXPECT_NE(summary.failure().find("cannot open the scene file"), std::string::npos);
  EXPECT_FALSE(state_->lease(worker, now_ + 100).has_value());
}

TEST_F(FarmStateTest, AFailedShotRetriesItsFailedTasksAndKeepsWhatIsDone) {
  const int64_t shot = submitFrame(0, 1);
  const int64_t worker = state_->registerWorker("w", 1, now_);
  const Lease good = leaseFor(worker), bad = leaseFor(worker);
  ASSERT_TRUE(complete(good.attempt_id(), storedChunk("good tile"), now_).accepted());
  ASSERT_TRUE(state_->fail(bad.attempt_id(), "scene.json: cannot open the scene file", now_).accepted());
  ASSERT_EQ(state_->summary(shot, now_).state(), SHOT_FAILED);
  EXPECT_FALSE(state_->lease(worker, now_ + 100).has_value());

  // The scene is back: the shot runs again, the failed tile only, with a fresh count.
  const ShotSummary retried = state_->retry(shot, now_);
  EXPECT_EQ(retried.state(), SHOT_RUNNING);
  EXPECT_TRUE(retried.failure().empty()) << retried.failure();
  const Lease again = leaseFor(worker);
  EXPECT_EQ(again.task_id(), bad.task_id());
  ASSERT_TRUE(complete(again.attempt_id(), storedChunk("bad tile, now good"), now_).accepted());
  const Lease assemble = leaseFor(worker);
  EXPECT_EQ(assemble.kind(), TASK_ASSEMBLE_FRAME);
  ASSERT_TRUE(complete(assemble.attempt_id(), storedChunk("frame"), now_).accepted());
  EXPECT_EQ(state_->summary(shot, now_).state(), SHOT_DONE);
  EXPECT_EQ(state_->summary(shot, now_).attempts(), 4);  // the good tile never ran again

  // Only a failed shot is retried.
  EXPECT_EQ(state_->retry(shot, now_).state(), SHOT_DONE);
}

TEST_F(FarmStateTest, ASubmitRetriedWithItsKeyMakesOneShot) {
  ShotSpec spec;
  spec.set_name("keyed");
  spec.set_scene("scene.json");
  spec.set_frame_start(0);
  spec.set_frame_end(0);
  spec.set_width(16);
  spec.set_height(16);
  spec.set_spp(1);
  spec.set_tile(16);
  spec.set_pipeline(PIPELINE_PT);
  const auto plan = planShot(spec);
  const int64_t first = state_->submit(spec, plan, now_, "key-1");
  EXPECT_EQ(state_->submit(spec, plan, now_ + 1, "key-1"), first);
  EXPECT_EQ(state_->shots(now_).size(), 1u);
  const int64_t other = state_->submit(spec, plan, now_, "key-2");
  EXPECT_NE(other, first);
  const int64_t unkeyed = state_->submit(spec, plan, now_), again = state_->submit(spec, plan, now_);
  EXPECT_NE(unkeyed, again);  // without a key every submit is a shot
  EXPECT_EQ(state_->shots(now_).size(), 4u);
}

TEST_F(FarmStateTest, WorkerFailingTooOftenIsBlocklistedForThatShot) {
  const int64_t shot = submitFrame(0, 10);
  const int64_t bad = state_->registerWorker("bad", 1, now_), good = state_->registerWorker("good", 1, now_);
  const Lease first = leaseFor(bad), second = leaseFor(bad);
  EXPECT_TRUE(state_->fail(first.attempt_id(), "out of memory", now_).accepted());
  EXPECT_TRUE(state_->fail(second.attempt_id(), "out of memory", now_).accepted());
  now_ += settings_.retryBackoffSeconds;
  EXPECT_FALSE(state_->lease(bad, now_).has_value());
  EXPECT_EQ(leaseFor(good).shot_id(), shot);
  EXPECT_EQ(state_->summary(shot, now_).state(), SHOT_RUNNING);
  const int64_t other = submitFrame();
  EXPECT_EQ(leaseFor(bad).shot_id(), other);  // blocklisted for one shot only
  // Registering again under the same name is no way out of the blocklist.
  const int64_t again = state_->registerWorker("bad", 1, now_);
  ASSERT_NE(again, bad);
  const auto lease = state_->lease(again, now_);
  EXPECT_TRUE(!lease || lease->shot_id() != shot) << "the re-registered worker leased the shot it is blocklisted for";
  EXPECT_EQ(state_->blocklist(shot).size(), 2u);  // the worker under both of its ids
}

TEST_F(FarmStateTest, ABlocklistIsListedAndClearedByHand) {
  const int64_t shot = submitFrame(0, 10);
  const int64_t bad = state_->registerWorker("bad", 1, now_);
  state_->registerWorker("good", 1, now_);  // alive: the shot does not fail when "bad" is blocklisted
  const Lease first = leaseFor(bad), second = leaseFor(bad);
  EXPECT_TRUE(state_->fail(first.attempt_id(), "out of memory", now_).accepted());
  EXPECT_TRUE(state_->fail(second.attempt_id(), "out of memory", now_).accepted());
  const auto entries = state_->blocklist(shot);
  ASSERT_EQ(entries.size(), 1u);
  EXPECT_EQ(entries[0].worker_id(), bad);
  EXPECT_EQ(entries[0].worker_name(), "bad");
  EXPECT_EQ(entries[0].failures(), 2);
  EXPECT_EQ(state_->blocklist(0).size(), 1u);
  EXPECT_TRUE(state_->blocklist(shot + 1).empty());
  now_ += settings_.retryBackoffSeconds;
  EXPECT_FALSE(state_->lease(bad, now_).has_value());
  state_->clearBlocklist(shot, bad, now_);  // the operator fixed its memory
  EXPECT_TRUE(state_->blocklist(shot).empty());
  EXPECT_EQ(leaseFor(bad).shot_id(), shot);
  EXPECT_THROW(state_->clearBlocklist(shot + 100, 0, now_), std::out_of_range);
}

TEST_F(FarmStateTest, PriorityCanChangeAfterSubmission) {
  const int64_t older = submitFrame(0), newer = submitFrame(0);
  const int64_t worker = state_->registerWorker("w", 1, now_);
  EXPECT_EQ(state_->setPriority(newer, 5, now_).priority(), 5);
  EXPECT_EQ(leaseFor(worker).shot_id(), newer);  // the raised shot goes first now
  EXPECT_EQ(state_->summary(older, now_).priority(), 0);
}

TEST_F(FarmStateTest, PoolsAndCapsDecideWhoMayLease) {
  ShotSpec spec;
  spec.set_name("pooled");
  spec.set_pipeline(PIPELINE_PT);
  spec.set_width(64);
  spec.set_height(64);
  spec.set_spp(1);
  spec.set_tile(16);  // 16 tiles: work for everyone
  spec.add_required_tags("gpu");
  spec.add_required_tags("big");
  spec.set_max_workers(1);
  const int64_t shot = state_->submit(spec, planShot(spec), now_);
  const int64_t plain = state_->registerWorker("plain", 1, now_);
  const int64_t gpuOnly = state_->registerWorker("gpu-only", 1, now_, {"gpu"});
  const int64_t first = state_->registerWorker("first", 2, now_, {"big", "gpu", "fast"});
  const int64_t second = state_->registerWorker("second", 1, now_, {"gpu", "big"});
  EXPECT_FALSE(state_->lease(plain, now_).has_value()) << "no tags";
  EXPECT_FALSE(state_->lease(gpuOnly, now_).has_value()) << "one of the two tags";
  const Lease a = leaseFor(first);
  EXPECT_EQ(a.shot_id(), shot);
  EXPECT_FALSE(state_->lease(second, now_).has_value()) << "the cap of one worker is reached";
  EXPECT_EQ(leaseFor(first).shot_id(), shot) << "the worker already on the shot may take another task";
  // Once the first worker's tasks are done, the second may come in.
  ASSERT_TRUE(complete(a.attempt_id(), storedChunk("a"), now_).accepted());
  EXPECT_FALSE(state_->lease(second, now_).has_value()) << "the first still holds its second task";
  // Another shot without requirements is anyone's.
  const int64_t open = submitFrame();
  EXPECT_EQ(leaseFor(plain).shot_id(), open);
}

TEST_F(FarmStateTest, ShotFailsWhenEveryLiveWorkerIsBlocklisted) {
  const int64_t shot = submitFrame(0, 10);
  const int64_t only = state_->registerWorker("only", 1, now_);
  state_->registerWorker("long gone", 1, now_ - 1000);
  const Lease first = leaseFor(only), second = leaseFor(only);
  EXPECT_TRUE(state_->fail(first.attempt_id(), "scene.json: cannot open the scene file", now_).accepted());
  EXPECT_EQ(state_->summary(shot, now_).state(), SHOT_RUNNING);
  EXPECT_TRUE(state_->fail(second.attempt_id(), "scene.json: cannot open the scene file", now_).accepted());
  const ShotSummary summary = state_->summary(shot, now_);
  EXPECT_EQ(summary.state(), SHOT_FAILED);
  EXPECT_NE(summary.failure().find("blocklisted"), std::string::npos) << summary.failure();
  EXPECT_NE(summary.failure().find("cannot open the scene file"), std::string::npos) << summary.failure();
}

// A leased task reports progress 0.2, then heartbeats every 9 s reporting `reported(i)`
// at the i-th: they keep the lease alive, but as they are no progress, the task is
// revoked as hung once hungSeconds have passed.
class HungTaskTest : public FarmStateTest {
 protected:
  void expectRevokedAsHung(const std::function<double(int)>& reported) {
    submitFrame();
    const int64_t worker = state_->registerWorker("w", 1, now_);
    const Lease lease = leaseFor(worker);
    now_ += 9;
    ASSERT_TRUE(state_->heartbeat(lease.attempt_id(), 0.2, now_).keep_going());
    const double lastProgress = now_;
    for (int i = 0; now_ + 9 <= lastProgress + settings_.hungSeconds; ++i) {
      now_ += 9;
      EXPECT_TRUE(state_->heartbeat(lease.attempt_id(), reported(i), now_).keep_going());
      EXPECT_EQ(state_->expireLeases(now_), 0);
    }
    now_ += 9;
    EXPECT_EQ(state_->expireLeases(now_), 1);
    EXPECT_FALSE(state_->heartbeat(lease.attempt_id(), 0.2, now_).keep_going());
  }
};

TEST_F(HungTaskTest, TaskWithoutProgressIsRevokedAsHung) {
  expectRevokedAsHung([](int) { return 0.2; });
}

// Found by the rpc_handlers fuzzer: a NaN progress failed the heartbeat's SQL (NaN is
// stored as NULL), so a worker reporting one lost its lease. It renews the lease and
// counts as no progress.
TEST_F(HungTaskTest, AHeartbeatWithoutAFiniteProgressRenewsTheLeaseButIsNoProgress) {
  expectRevokedAsHung([](int i) {
    const double unknown[] = {std::nan(""), std::numeric_limits<double>::infinity(),
                              -std::numeric_limits<double>::infinity()};
    return unknown[i % 3];
  });
}

TEST_F(FarmStateTest, CancelStopsLeasesAndTellsRunningWorkers) {
  const int64_t shot = submitFrame();
  const int64_t worker = state_->registerWorker("w", 1, now_);
  const Lease lease = leaseFor(worker);
  EXPECT_EQ(state_->cancel(shot, now_).state(), SHOT_CANCELLED);
  EXPECT_FALSE(state_->heartbeat(lease.attempt_id(), 0.5, now_).keep_going());
  EXPECT_FALSE(complete(lease.attempt_id(), storedChunk("x"), now_).accepted());
  EXPECT_FALSE(state_->lease(worker, now_).has_value());
  EXPECT_THROW(state_->summary(shot + 100, now_), std::out_of_range);
}

TEST_F(FarmStateTest, RestartKeepsFinishedWorkAndGivesRunningLeasesGrace) {
  const int64_t shot = submitFrame();
  const int64_t worker = state_->registerWorker("w", 1, now_);
  const Lease done = leaseFor(worker), running = leaseFor(worker);
  ASSERT_TRUE(complete(done.attempt_id(), storedChunk("a"), now_).accepted());
  state_.reset();  // the scheduler dies...
  now_ += 60;      // ...and comes back a minute later, past the lease
  open();
  EXPECT_EQ(state_->expireLeases(now_), 0) << "a lease expired while nobody could renew it";
  EXPECT_TRUE(complete(running.attempt_id(), storedChunk("b"), now_).accepted());
  const Lease assemble = leaseFor(worker);
  EXPECT_EQ(assemble.kind(), TASK_ASSEMBLE_FRAME);
  EXPECT_TRUE(complete(assemble.attempt_id(), storedChunk("f"), now_).accepted());
  EXPECT_EQ(state_->summary(shot, now_).state(), SHOT_DONE);
  EXPECT_EQ(state_->summary(shot, now_).attempts(), 3);  // nothing ran twice
}

TEST_F(FarmStateTest, FollowUpTilesJoinTheShotAndTheCompositeWaitsForThem) {
  const int64_t shot = submitFiltered();
  const int64_t worker = state_->registerWorker("w", 1, now_);
  const Lease interpolate = leaseFor(worker);
  ASSERT_EQ(interpolate.kind(), TASK_INTERPOLATE);
  const std::vector<TaskParams> tiles = {rerenderTile(0, 0), rerenderTile(8, 0)};
  ASSERT_TRUE(complete(interpolate.attempt_id(), storedChunk("i"), now_, tiles).accepted());
  EXPECT_EQ(state_->summary(shot, now_).tasks_total(), 4);

  // The composite is not ready before the follow-ups are done; then it gets all three inputs.
  const Lease first = leaseFor(worker);
  const Lease second = leaseFor(worker);
  EXPECT_EQ(first.kind(), TASK_RENDER_TILE);
  EXPECT_EQ(second.kind(), TASK_RENDER_TILE);
  EXPECT_FALSE(state_->lease(worker, now_).has_value());
  ASSERT_TRUE(complete(first.attempt_id(), storedChunk("t1"), now_).accepted());
  EXPECT_FALSE(state_->lease(worker, now_).has_value());
  ASSERT_TRUE(complete(second.attempt_id(), storedChunk("t2"), now_).accepted());
  const Lease composite = leaseFor(worker);
  ASSERT_EQ(composite.kind(), TASK_COMPOSITE);
  ASSERT_EQ(composite.inputs_size(), 3);
  EXPECT_EQ(composite.input_kinds(0), TASK_INTERPOLATE);
  EXPECT_EQ(composite.input_kinds(1), TASK_RENDER_TILE);
  EXPECT_EQ(composite.input_params(2).window().x0(), 8);
  ASSERT_TRUE(complete(composite.attempt_id(), storedChunk("c"), now_).accepted());
  EXPECT_EQ(state_->summary(shot, now_).state(), SHOT_DONE);
  const auto outputs = state_->outputs(shot);
  ASSERT_EQ(outputs.size(), 1u);
  EXPECT_EQ(outputs[0].second.sha256(), storedChunk("c").sha256());
}

TEST_F(FarmStateTest, ReportRecordsCarryCoreSecondsAndMetrics) {
  const int64_t shot = submitFrame();
  const int64_t worker = state_->registerWorker("w", 1, now_);
  const Lease tile = leaseFor(worker);
  CompleteRequest request;
  request.set_attempt_id(tile.attempt_id());
  *request.mutable_output() = storedChunk("t");
  request.set_core_seconds(2.5);
  (*request.mutable_metrics())["samples"] = 1024;
  // Found by the rpc_handlers fuzz target: a NaN figure made the completion fail with
  // INTERNAL (SQLite stores NaN as NULL). The output is kept and the figure left out.
  (*request.mutable_metrics())["relmse"] = std::nan("");
  ASSERT_TRUE(state_->complete(request, now_).accepted());
  const auto [spec, records] = state_->taskRecords(shot);
  EXPECT_EQ(records[0].metrics.count("relmse"), 0u);
  EXPECT_EQ(spec.name(), "shot");
  ASSERT_EQ(records.size(), 3u);
  EXPECT_TRUE(records[0].done);
  EXPECT_EQ(records[0].coreSeconds, 2.5);
  EXPECT_EQ(records[0].metrics.at("samples"), 1024);
  EXPECT_FALSE(records[1].done);
  EXPECT_TRUE(records[1].metrics.empty());
}

TEST(Schema, MigratesOnceAndRefusesANewerDatabase) {
  const auto file = test_support::processTemporaryFolder("pathfarm_schema") / "schema.db";
  std::filesystem::remove(file);
  {
    Database db(file.string());
    migrate(db);
    EXPECT_EQ(schemaVersion(db), 14);
    EXPECT_NO_THROW(db.execute("SELECT lost FROM tasks"));  // migration 3's column
    EXPECT_NO_THROW(db.execute("SELECT attempt_id, params FROM follow_ups"));  // migration 11's table
    EXPECT_NO_THROW(db.execute("SELECT shot_id, after_id FROM shot_waits"));  // migration 13's table
    EXPECT_NO_THROW(db.execute("SELECT released FROM chunks"));  // migration 14's column
    migrate(db);  // nothing to do the second time
    db.execute("PRAGMA user_version = 99");
    EXPECT_THROW(migrate(db), DatabaseError);
  }
  std::filesystem::remove(file);
}

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdeprecated-declarations"  // a spec as schema 11 stored it
TEST(Schema, ShotsStoredWithAPipelineNameGetItsValue) {
  const auto file = test_support::processTemporaryFolder("pathfarm_schema") / "legacy.db";
  std::filesystem::remove(file);
  {
    Database db(file.string());
    migrate(db, 11);
    const auto insert = [&](int64_t id, const std::string& pipeline) {
      ShotSpec legacy;
      legacy.set_name("shot");
      legacy.set_legacy_pipeline_name(pipeline);
      db.query("INSERT INTO shots (id, name, spec, state, priority, tasks_left, submitted_at) "
               "VALUES (?1, 'shot', ?2, 1, 0, 0, 0)")
          .bind(1, id)
          .bindBlob(2, legacy.SerializeAsString())
          .step();
    };
    insert(1, "dui");
    insert(2, "tmlt");
    insert(3, "no such pipeline");
    migrate(db);
    std::map<int64_t, ShotSpec> specs;
    Statement& read = db.query("SELECT id, spec FROM shots");
    while (read.step()) specs[read.integer(0)].ParseFromString(read.blob(1));
    read.reset();
    EXPECT_EQ(specs[1].pipeline(), PIPELINE_DUI);
    EXPECT_EQ(specs[2].pipeline(), PIPELINE_TMLT);
    EXPECT_EQ(specs[3].pipeline(), PIPELINE_UNSPECIFIED);
    for (const auto& [id, spec] : specs) {
      EXPECT_TRUE(spec.legacy_pipeline_name().empty()) << id;
      EXPECT_EQ(spec.name(), "shot");
    }
  }
  std::filesystem::remove(file);
}
#pragma GCC diagnostic pop

}  // namespace
}  // namespace pathfarm::farm
