// Retention: shots finished longer ago than FarmSettings::retainSeconds go with their
// records, and so do the chunks nothing kept names; everything else stays.
#include <algorithm>

#include "scheduler/farm_state_fixture.h"

namespace pathfarm::farm {
namespace {

// Whether `list` holds the digest FarmStateTest::storedChunk gives `name`.
bool has(const std::vector<std::string>& list, const std::string& name) {
  return std::find(list.begin(), list.end(), std::string(64 - name.size(), '0') + name) != list.end();
}

TEST_F(FarmStateTest, RetentionDeletesOldFinishedShotsAndTheChunksOnlyTheyNamed) {
  settings_.retainSeconds = 100;
  open();
  const int64_t worker = state_->registerWorker("w", 1, now_);
  storedChunk("orphan");  // uploaded, never named by a task

  // An old shot, done: two tiles and its frame.
  const int64_t old = submitFrame();
  ASSERT_TRUE(complete(leaseFor(worker).attempt_id(), storedChunk("shared"), now_).accepted());
  ASSERT_TRUE(complete(leaseFor(worker).attempt_id(), storedChunk("mine"), now_).accepted());
  ASSERT_TRUE(complete(leaseFor(worker).attempt_id(), storedChunk("frame"), now_).accepted());
  ASSERT_EQ(state_->summary(old, now_).state(), SHOT_DONE);

  // A shot still running names one of the old shot's chunks (the same tile bytes), and an
  // uploaded scene file as its input.
  ShotSpec spec;
  spec.set_name("running");
  spec.set_pipeline(PIPELINE_PT);
  spec.set_width(64);
  spec.set_height(32);
  spec.set_spp(1);
  spec.set_tile(32);
  InputFile* scene = spec.add_inputs();
  scene->set_path("scene.json");
  *scene->mutable_chunk() = storedChunk("scene");
  const int64_t running = state_->submit(spec, planShot(spec), now_);
  ASSERT_TRUE(complete(leaseFor(worker).attempt_id(), storedChunk("shared"), now_).accepted());

  now_ += 50;
  EXPECT_TRUE(state_->collectGarbage(now_).shots.empty()) << "deleted before its time";
  now_ += 60;
  storedChunk("fresh");  // uploaded just now, for a shot to come
  const FarmState::Collected collected = state_->collectGarbage(now_);
  EXPECT_EQ(collected.shots, std::vector<int64_t>{old});
  EXPECT_EQ(collected.chunks.size(), 3u);
  for (const char* gone : {"mine", "frame", "orphan"}) EXPECT_TRUE(has(collected.chunks, gone)) << gone;
  EXPECT_THROW(state_->summary(old, now_), std::out_of_range);
  EXPECT_EQ(state_->summary(running, now_).state(), SHOT_RUNNING);
  EXPECT_EQ(state_->taskDetails(running, std::nullopt, 0, 10).tasks.size(), 3u);
  for (const char* kept : {"shared", "scene", "fresh"}) EXPECT_FALSE(has(collected.chunks, kept)) << kept;

  // What was deleted is not deleted twice; the running shot finishes as before.
  EXPECT_TRUE(state_->collectGarbage(now_).chunks.empty());
  ASSERT_TRUE(complete(leaseFor(worker).attempt_id(), storedChunk("other"), now_).accepted());
  ASSERT_TRUE(complete(leaseFor(worker).attempt_id(), storedChunk("frame2"), now_).accepted());
  EXPECT_EQ(state_->summary(running, now_).state(), SHOT_DONE);
}

TEST_F(FarmStateTest, WithoutRetentionNothingIsDeleted) {
  const int64_t worker = state_->registerWorker("w", 1, now_);
  const int64_t shot = submitFrame();
  for (const char* chunk : {"a", "b", "frame"})
    ASSERT_TRUE(complete(leaseFor(worker).attempt_id(), storedChunk(chunk), now_).accepted());
  storedChunk("orphan");
  const FarmState::Collected collected = state_->collectGarbage(now_ + 1e9);
  EXPECT_TRUE(collected.shots.empty());
  EXPECT_TRUE(collected.chunks.empty());
  EXPECT_EQ(state_->summary(shot, now_).state(), SHOT_DONE);
}

}  // namespace
}  // namespace pathfarm::farm

namespace pathfarm::farm {
namespace {

// Whether `list` is exactly the digests FarmStateTest::storedChunk gives `names`, in any order.
bool holdsExactly(std::vector<std::string> list, const std::vector<std::string>& names) {
  std::vector<std::string> expected;
  for (const std::string& name : names) expected.push_back(std::string(64 - name.size(), '0') + name);
  std::sort(list.begin(), list.end());
  std::sort(expected.begin(), expected.end());
  return list == expected;
}

TEST_F(FarmStateTest, ChunksReleasedBeforeARestartAreListedForTheSweepAtStartUntilStoredAgain) {
  const int64_t worker = state_->registerWorker("w1", 1, now_);
  submitFrame();
  ASSERT_TRUE(complete(leaseFor(worker).attempt_id(), storedChunk("left"), now_).accepted());
  ASSERT_TRUE(complete(leaseFor(worker).attempt_id(), storedChunk("right"), now_).accepted());
  ASSERT_TRUE(complete(leaseFor(worker).attempt_id(), storedChunk("frame"), now_).accepted());
  // The scheduler is killed after the release is committed, before it removes the files.
  open();
  const auto sha = [](const std::string& name) { return std::string(64 - name.size(), '0') + name; };
  std::vector<std::string> released = state_->releasedChunks();
  std::sort(released.begin(), released.end());
  EXPECT_EQ(released, (std::vector<std::string>{sha("left"), sha("right")}));
  storedChunk("left");  // made again: kept again
  EXPECT_EQ(state_->releasedChunks(), std::vector<std::string>{sha("right")});
}

TEST_F(FarmStateTest, TilesAreReleasedOnceTheirFrameIsAssembledAndMadeAgainOnlyForAReader) {
  const int64_t w1 = state_->registerWorker("w1", 1, now_), w2 = state_->registerWorker("w2", 1, now_);
  const int64_t first = submitFrame();
  ASSERT_TRUE(complete(leaseFor(w1).attempt_id(), storedChunk("shared"), now_).accepted());
  ASSERT_TRUE(complete(leaseFor(w1).attempt_id(), storedChunk("mine"), now_).accepted());
  EXPECT_TRUE(state_->takeReleasedChunks().empty()) << "released before their frame was assembled";

  // A second shot (leased first) renders a tile of the same bytes; its frame is not assembled yet.
  submitFrame(/*priority=*/5);
  ASSERT_TRUE(complete(leaseFor(w1).attempt_id(), storedChunk("shared"), now_).accepted());
  const Lease stillRendering = leaseFor(w1);
  ASSERT_EQ(stillRendering.kind(), TASK_RENDER_TILE);

  const Lease assembly = leaseFor(w2);
  ASSERT_EQ(assembly.kind(), TASK_ASSEMBLE_FRAME);
  ASSERT_TRUE(complete(assembly.attempt_id(), storedChunk("frame"), now_).accepted());
  EXPECT_TRUE(holdsExactly(state_->takeReleasedChunks(), {"mine"}))
      << "the frame is kept, and so is the tile another shot's assembly still reads";
  EXPECT_TRUE(state_->takeReleasedChunks().empty()) << "each tile is released once";

  // A late worker asking for a released tile makes nothing run again...
  const std::string mine = std::string(64 - 4, '0') + "mine";
  EXPECT_EQ(state_->requeueProducersOf(mine, now_), 0);
  EXPECT_EQ(state_->summary(first, now_).state(), SHOT_DONE);
  // ...an assembly that runs again does.
  state_->requeueTask(first, assembly.task_id(), now_);
  EXPECT_EQ(state_->requeueProducersOf(mine, now_), 1);
}

}  // namespace
}  // namespace pathfarm::farm

namespace pathfarm::farm {
namespace {

// A filtering frame with its evaluation: a reference, an interpolation (an intermediate),
// the composite (the shot's frame) and the evaluate task reading the reference and the
// frame.
class ReleaseTest : public FarmStateTest {
 protected:
  // Runs every task, each output named after its kind; returns what was released when the
  // composite finished and when the evaluation did.
  std::pair<std::vector<std::string>, std::vector<std::string>> runFilteredFrame() {
    PlannedTask reference{TASK_ASSEMBLE_FRAME, {}, {}};
    reference.params.set_role(ROLE_REFERENCE);
    const std::vector<PlannedTask> plan = {
        reference, {TASK_INTERPOLATE, {}, {}}, {TASK_COMPOSITE, {}, {1}, true}, {TASK_EVALUATE, {}, {0, 2}}};
    state_->submit(filteredSpec(), plan, now_);
    const int64_t worker = state_->registerWorker("w", 1, now_);
    std::vector<std::string> afterComposite, afterEvaluation;
    for (int task = 0; task < 4; ++task) {
      const Lease lease = leaseFor(worker);
      const std::string name = TaskKind_Name(lease.kind()).substr(5, 10);  // letters only, short enough
      EXPECT_TRUE(complete(lease.attempt_id(), storedChunk(name), now_).accepted()) << name;
      if (lease.kind() == TASK_COMPOSITE) afterComposite = state_->takeReleasedChunks();
      if (lease.kind() == TASK_EVALUATE) afterEvaluation = state_->takeReleasedChunks();
    }
    return {afterComposite, afterEvaluation};
  }
};

TEST_F(ReleaseTest, AnIntermediateIsReleasedOnceReadButAFrameAndAReferenceAreKept) {
  const auto [afterComposite, afterEvaluation] = runFilteredFrame();
  EXPECT_TRUE(holdsExactly(afterComposite, {"INTERPOLAT"})) << "the interpolation, read by the composite alone";
  EXPECT_TRUE(afterEvaluation.empty()) << "the evaluation read the reference (kept for later shots) and the frame";
}

TEST_F(ReleaseTest, KeepIntermediatesKeepsEveryChunk) {
  settings_.keepIntermediates = true;
  open();
  const auto [afterComposite, afterEvaluation] = runFilteredFrame();
  EXPECT_TRUE(afterComposite.empty());
  EXPECT_TRUE(afterEvaluation.empty());
}

}  // namespace
}  // namespace pathfarm::farm
