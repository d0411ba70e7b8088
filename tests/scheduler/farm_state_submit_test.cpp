// Submit inserts a shot's tasks a batch per transaction: a shot larger than a batch is
// whole when submit returns, one whose insertion fails leaves nothing, and a shot whose
// submit was cut short (the scheduler died) is neither leased nor kept.
#include "scheduler/farm_state_fixture.h"
#include "scheduler/sqlite_db.h"

namespace pathfarm::farm {
namespace {

std::vector<PlannedTask> noopPlan(size_t count) {
  std::vector<PlannedTask> plan(count);
  for (PlannedTask& task : plan) task.kind = TASK_NOOP;
  return plan;
}

ShotSpec noopSpec() {
  ShotSpec spec;
  spec.set_name("many");
  spec.set_pipeline(PIPELINE_NOOP);
  return spec;
}

TEST_F(FarmStateTest, AShotOfManyBatchesIsWholeWhenSubmitReturns) {
  const size_t count = 3 * FarmState::kTasksPerTransaction + 7;
  std::vector<PlannedTask> plan = noopPlan(count);
  plan.back().dependencies = {0, count - 2};  // across batches
  const int64_t shot = state_->submit(noopSpec(), plan, now_);
  const ShotSummary summary = state_->summary(shot, now_);
  EXPECT_EQ(summary.tasks_total(), static_cast<int64_t>(count));
  EXPECT_EQ(summary.tasks_done(), 0);
  Database db((folder_ / "farm.db").string());
  Statement& deps = db.query("SELECT COUNT(*) FROM task_deps");
  ASSERT_TRUE(deps.step());
  EXPECT_EQ(deps.integer(0), 2);
}

TEST_F(FarmStateTest, ASubmitThatFailsPartWayLeavesNothingBehind) {
  std::vector<PlannedTask> plan = noopPlan(2 * FarmState::kTasksPerTransaction + 3);
  plan.back().dependencies = {plan.size()};  // not an earlier task: the last batch throws
  EXPECT_THROW(state_->submit(noopSpec(), plan, now_, "key"), std::out_of_range);
  EXPECT_TRUE(state_->shots(now_).empty());
  Database db((folder_ / "farm.db").string());
  Statement& tasks = db.query("SELECT COUNT(*) FROM tasks");
  ASSERT_TRUE(tasks.step());
  EXPECT_EQ(tasks.integer(0), 0) << "the batches before the failure were left behind";
  // The key is free again: the client's next try makes the shot.
  plan.back().dependencies = {0};
  EXPECT_NO_THROW(state_->submit(noopSpec(), plan, now_, "key"));
  EXPECT_EQ(state_->shots(now_).size(), 1u);
}

TEST_F(FarmStateTest, AShotStillBuildingIsNotLeasedAndGoesWhenTheSchedulerStartsAgain) {
  const int64_t worker = state_->registerWorker("w", 1, now_);
  const int64_t cut = state_->submit(noopSpec(), noopPlan(4), now_, "cut-short");
  {
    // As if the scheduler had died between two batches of this submit.
    Database db((folder_ / "farm.db").string());
    db.query("UPDATE shots SET building = 1 WHERE id = ?1").bind(1, cut).run();
  }
  EXPECT_FALSE(state_->lease(worker, now_).has_value()) << "a task of a shot still building was leased";
  const int64_t whole = submitFrame();
  EXPECT_EQ(leaseFor(worker).shot_id(), whole);

  state_.reset();
  open();
  EXPECT_THROW(state_->summary(cut, now_), std::out_of_range);
  EXPECT_EQ(state_->summary(whole, now_).state(), SHOT_RUNNING);
  const int64_t again = state_->submit(noopSpec(), noopPlan(4), now_, "cut-short");
  EXPECT_NE(again, cut) << "the retried submit found the shot that was dropped";
  EXPECT_EQ(state_->summary(again, now_).tasks_total(), 4);
}

}  // namespace
}  // namespace pathfarm::farm
