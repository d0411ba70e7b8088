#pragma once
// FarmState on a fresh database in a folder of its own, with a clock the test controls,
// and the small steps most of its tests take: submit a frame, lease, store, complete.
#include <gtest/gtest.h>

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "scheduler/farm_state.h"

namespace pathfarm::farm {

class FarmStateTest : public ::testing::Test {
 protected:
  void SetUp() override {
    folder_ = std::filesystem::temp_directory_path() /
              ("pathfarm_state_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    std::filesystem::remove_all(folder_);
    std::filesystem::create_directories(folder_);
    settings_.leaseSeconds = 10;
    settings_.hungSeconds = 100;
    settings_.retryBackoffSeconds = 2;
    settings_.blocklistAfter = 2;
    open();
  }
  void TearDown() override {
    state_.reset();
    std::filesystem::remove_all(folder_);
  }
  void open() { state_ = std::make_unique<FarmState>((folder_ / "farm.db").string(), settings_, now_); }

  // One frame of 2x1 tiles plus its assembly, as the planner makes for "pt", waiting for
  // the shots `after`.
  int64_t submitFrame(int priority = 0, int maxAttempts = 3, const std::vector<int64_t>& after = {}) {
    ShotSpec spec;
    spec.set_name("shot");
    spec.set_pipeline(PIPELINE_PT);
    spec.set_width(64);
    spec.set_height(32);
    spec.set_spp(1);
    spec.set_tile(32);
    spec.set_priority(priority);
    spec.set_max_attempts(maxAttempts);
    for (const int64_t shot : after) spec.add_after_shots(shot);
    return state_->submit(spec, planShot(spec), now_);
  }
  // The frames of filteredSpec() are 16x8 in tiles of 8: a re-render of the tile at (x0, y0).
  static ShotSpec filteredSpec() {
    ShotSpec spec;
    spec.set_name("filtered");
    spec.set_pipeline(PIPELINE_DI);
    spec.set_width(16);
    spec.set_height(8);
    spec.set_tile(8);
    spec.set_spp(4);
    return spec;
  }
  // An interpolation and the composite waiting for it, on filteredSpec()'s frames.
  int64_t submitFiltered() {
    const std::vector<PlannedTask> plan = {{TASK_INTERPOLATE, {}, {}}, {TASK_COMPOSITE, {}, {0}, true}};
    return state_->submit(filteredSpec(), plan, now_);
  }
  static TaskParams rerenderTile(int x0, int y0) {
    TaskParams tile;
    tile.set_role(ROLE_RERENDER);
    tile.set_spp(4);
    PixelWindow* w = tile.mutable_window();
    w->set_x0(x0);
    w->set_y0(y0);
    w->set_x1(x0 + 8);
    w->set_y1(y0 + 8);
    return tile;
  }
  ChunkRef storedChunk(const std::string& name) {
    ChunkRef ref;
    ref.set_sha256(std::string(64 - name.size(), '0') + name);
    ref.set_size(10);
    state_->recordChunk(ref, now_);
    return ref;
  }
  ReportReply complete(int64_t attemptId, const ChunkRef& output, double now,
                       const std::vector<TaskParams>& followUps = {}) {
    // As a worker does: the follow-ups staged first, then the completion.
    if (!followUps.empty()) {
      google::protobuf::RepeatedPtrField<TaskParams> batch(followUps.begin(), followUps.end());
      if (const ReportReply staged = state_->stageFollowUps(attemptId, batch); !staged.accepted()) return staged;
    }
    CompleteRequest request;
    request.set_attempt_id(attemptId);
    *request.mutable_output() = output;
    return state_->complete(request, now);
  }
  Lease leaseFor(int64_t worker) {
    auto lease = state_->lease(worker, now_);
    EXPECT_TRUE(lease.has_value());
    return lease.value_or(Lease{});
  }

  std::filesystem::path folder_;
  FarmSettings settings_;
  double now_ = 1000;
  std::unique_ptr<FarmState> state_;
};

}  // namespace pathfarm::farm
