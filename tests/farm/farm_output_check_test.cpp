// The scheduler checks a task's output before it accepts the completion: a tile holding
// a NaN, a tile of the wrong size or bytes that are no image are refused, the attempt
// fails as the worker's fault, and honest workers then make the frame.
#include <cmath>
#include <limits>

#include "farm/farm_fixture.h"
#include "image/exr_io.h"
#include "worker/scheduler_link.h"

namespace pathfarm::farmtest {
namespace {

std::string tileBytes(int width, int height, float value) {
  FrameImage image(width, height);
  for (const char* channel : {"R", "G", "B"}) image.addChannel(channel).assign(image.pixelCount(), 0.25f);
  image.channel("G")[image.pixelCount() / 2] = value;
  image.attributes()["pathfarm.nonfinite_samples"] = "0";
  return encodeExr(image, ExrCompression::Fast);
}

TEST_F(FarmTest, AnOutputWithANaNOrTheWrongSizeIsRefusedAtCompletion) {
  SchedulerConfig config;
  config.retryBackoffSeconds = 0.1;
  const std::string address = startScheduler(config);
  const FarmDatabase db = database();

  RenderSpec spec;
  spec.name = "checked-outputs";
  spec.width = 64;
  spec.height = 32;
  spec.tile = 32;
  const int64_t id = client().submit(shotSpec(spec));

  farm::SchedulerLink link(address, "");
  farm::RegisterReply registration;
  ASSERT_TRUE(link.registerWorker("sloppy", 1, {}, registration).ok());
  const auto deliver = [&](const std::string& bytes) {
    farm::LeaseReply leased;
    farm::WorkerSession used;
    EXPECT_TRUE(link.lease(5, leased, used).ok());
    EXPECT_EQ(leased.lease().kind(), farm::TASK_RENDER_TILE);
    farm::CompleteRequest request;
    request.set_attempt_id(leased.lease().attempt_id());
    EXPECT_TRUE(link.putChunk(bytes, *request.mutable_output()).ok());
    farm::ReportReply reply;
    EXPECT_TRUE(link.complete(request, reply).ok());
    EXPECT_FALSE(reply.accepted()) << "the output was taken";
    EXPECT_EQ(db.rows("SELECT state, failure_class FROM attempts WHERE id = " +
                      std::to_string(leased.lease().attempt_id()))[0],
              (std::vector<std::string>{"2", "worker_fault"}));
    return reply.reason();
  };
  const std::string nan = deliver(tileBytes(32, 32, std::numeric_limits<float>::quiet_NaN()));
  EXPECT_TRUE(contains(nan, "non-finite value in channel G at pixel (0, 16)")) << nan;
  const std::string small = deliver(tileBytes(16, 32, 0.5f));
  EXPECT_TRUE(contains(small, "16x32, its window 32x32")) << small;
  EXPECT_EQ(db.integer("SELECT COUNT(*) FROM tasks WHERE state = 3"), 0) << "a refused output made a task done";

  // Honest workers finish the shot with the frame a local render makes.
  startWorker("w1");
  const farm::ShotSummary summary = waitForShot(id, 30s);
  ASSERT_EQ(summary.state(), farm::SHOT_DONE) << describe(summary);
  expectSameFrames(fetchFrames(id, "fetched"), renderLocally(spec), spec);
}

}  // namespace
}  // namespace pathfarm::farmtest
