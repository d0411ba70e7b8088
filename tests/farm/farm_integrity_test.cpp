// What a worker sends is checked: a chunk whose bytes do not match its announced digest
// or size is refused and never stored, and a completion under a lease that expired is
// refused, so neither can end up in a frame.
#include <grpcpp/grpcpp.h>

#include "farm/farm_fixture.h"
#include "pathfarm/worker_service.grpc.pb.h"
#include "proto/wire/connection.h"
#include "proto/wire/sha256.h"
#include "worker/scheduler_link.h"

namespace pathfarm::farmtest {
namespace {

// PutChunk with whatever reference the caller announces (SchedulerLink always tells the
// truth), in the given worker session.
grpc::Status putAnnouncing(const std::string& address, const farm::WorkerSession& session,
                           const farm::ChunkRef& announced, const std::string& bytes) {
  const auto stub = farm::WorkerService::NewStub(farm::makeChannel(address));
  grpc::ClientContext context;
  context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(10));
  farm::attachSession(context, session);
  farm::PutChunkReply reply;
  auto writer = stub->PutChunk(&context, &reply);
  farm::ChunkPart part;
  *part.mutable_ref() = announced;
  part.set_data(bytes);
  writer->Write(part);
  writer->WritesDone();
  return writer->Finish();
}

farm::ChunkRef refOf(const std::string& sha256, size_t size) {
  farm::ChunkRef ref;
  ref.set_sha256(sha256);
  ref.set_size(static_cast<int64_t>(size));
  return ref;
}

// Files under the store that are not finished chunks (a .partial left behind).
std::vector<fs::path> leftovers(const fs::path& store) {
  std::vector<fs::path> found;
  for (const auto& entry : fs::recursive_directory_iterator(store))
    if (entry.is_regular_file() && entry.path().extension() == ".partial") found.push_back(entry.path());
  return found;
}

TEST_F(FarmTest, CorruptUploadsAndLateCompletionsAreRefused) {
  SchedulerConfig config;
  config.leaseSeconds = 1;
  const std::string address = startScheduler(config);
  const FarmDatabase db = database();
  const auto chunkRows = [&](const std::string& sha) {
    return db.integer("SELECT COUNT(*) FROM chunks WHERE sha256 = '" + sha + "'");
  };

  // --- Corrupt uploads: the same length, another digest; and a size that is a lie.
  const std::string sent = "the bytes that were really sent, 0123456789";
  const std::string claimed = "the bytes the digest was computed for, 0123";
  ASSERT_EQ(sent.size(), claimed.size());
  const std::string sentSha = farm::sha256Hex(sent), claimedSha = farm::sha256Hex(claimed);

  farm::SchedulerLink link(address, "");
  farm::RegisterReply registration;
  ASSERT_TRUE(link.registerWorker("silent", 1, {}, registration).ok());
  const farm::WorkerSession session{registration.worker_id(), registration.session_key()};
  const grpc::Status mismatch = putAnnouncing(address, session, refOf(claimedSha, sent.size()), sent);
  EXPECT_EQ(mismatch.error_code(), grpc::StatusCode::DATA_LOSS) << mismatch.error_message();
  const grpc::Status truncated = putAnnouncing(address, session, refOf(sentSha, sent.size() + 100), sent);
  EXPECT_EQ(truncated.error_code(), grpc::StatusCode::DATA_LOSS) << truncated.error_message();
  for (const std::string& sha : {sentSha, claimedSha}) {
    EXPECT_FALSE(fs::exists(chunkFile(sha))) << "a refused chunk is in the store: " << sha;
    EXPECT_EQ(chunkRows(sha), 0) << "a refused chunk is in the database: " << sha;
  }
  EXPECT_TRUE(leftovers(storeFolder()).empty()) << "partial files left in the store";

  // Without a worker's session, or with a forged one, nothing is stored.
  EXPECT_EQ(putAnnouncing(address, {}, refOf(sentSha, sent.size()), sent).error_code(),
            grpc::StatusCode::UNAUTHENTICATED);
  EXPECT_EQ(putAnnouncing(address, {session.workerId, "forged"}, refOf(sentSha, sent.size()), sent).error_code(),
            grpc::StatusCode::UNAUTHENTICATED);
  EXPECT_EQ(chunkRows(sentSha), 0);

  // The honest upload of the same bytes is stored where the checks above looked.
  farm::ChunkRef stored;
  const grpc::Status honest = link.putChunk(sent, stored);
  ASSERT_TRUE(honest.ok()) << honest.error_message();
  EXPECT_EQ(stored.sha256(), sentSha);
  EXPECT_EQ(readFile(chunkFile(sentSha)), sent);
  EXPECT_EQ(chunkRows(sentSha), 1);

  // --- A late completion: a registered worker leases a tile and goes silent.
  RenderSpec spec;
  spec.name = "late-completion";
  spec.frameStart = spec.frameEnd = 2;
  spec.width = 64;
  spec.height = 32;
  spec.tile = 32;
  const int64_t id = client().submit(shotSpec(spec));

  farm::LeaseReply leased;
  farm::WorkerSession used;
  ASSERT_TRUE(link.lease(5, leased, used).ok());
  ASSERT_EQ(used.workerId, registration.worker_id());
  ASSERT_TRUE(leased.has_task());
  ASSERT_EQ(leased.lease().kind(), farm::TASK_RENDER_TILE);
  const int64_t attempt = leased.lease().attempt_id(), task = leased.lease().task_id();
  const std::string attemptState = "SELECT state FROM attempts WHERE id = " + std::to_string(attempt);
  EXPECT_EQ(db.integer(attemptState), 0);

  // Another registered worker may neither lease as the silent one nor report on its attempt.
  farm::SchedulerLink intruder(address, "");
  farm::RegisterReply intruderRegistration;
  ASSERT_TRUE(intruder.registerWorker("intruder", 1, {}, intruderRegistration).ok());
  {
    // A lease in its own session that names the silent worker.
    const auto stub = farm::WorkerService::NewStub(farm::makeChannel(address));
    grpc::ClientContext context;
    context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(10));
    farm::attachSession(context, {intruderRegistration.worker_id(), intruderRegistration.session_key()});
    farm::LeaseRequest request;
    request.set_worker_id(registration.worker_id());
    farm::LeaseReply stolen;
    EXPECT_EQ(stub->LeaseTask(&context, request, &stolen).error_code(), grpc::StatusCode::PERMISSION_DENIED);
  }
  farm::HeartbeatReply intruderBeat;
  EXPECT_EQ(intruder.heartbeat(attempt, 0.5, intruderBeat).error_code(), grpc::StatusCode::PERMISSION_DENIED);
  farm::ReportReply intruderFailure;
  farm::FailRequest blame;
  blame.set_attempt_id(attempt);
  blame.set_reason("blame the silent worker");
  EXPECT_EQ(intruder.fail(blame, intruderFailure).error_code(),
            grpc::StatusCode::PERMISSION_DENIED);
  farm::FollowUpsRequest planted;
  planted.set_attempt_id(attempt);
  planted.add_follow_ups()->set_role(farm::ROLE_RERENDER);
  farm::ReportReply plantedReply;
  EXPECT_EQ(intruder.reportFollowUps(planted, plantedReply).error_code(), grpc::StatusCode::PERMISSION_DENIED);
  farm::Lease peek = leased.lease();
  EXPECT_EQ(intruder.leaseInputs(peek).error_code(), grpc::StatusCode::PERMISSION_DENIED);
  EXPECT_EQ(db.integer(attemptState), 0) << "the intruder's failure report was taken";
  EXPECT_EQ(db.integer("SELECT COUNT(*) FROM worker_failures"), 0);

  ASSERT_TRUE(waitUntil([&] { return db.integer(attemptState) == 3; }, 10s))
      << "the lease of attempt " << attempt << " did not expire";

  // The silent worker now delivers a result: the chunk is stored (any worker may store
  // chunks), but the completion under the dead lease is refused, as are its reports.
  const std::string bogus = "not a tile: a result that must never reach a frame";
  farm::ChunkRef bogusRef;
  ASSERT_TRUE(link.putChunk(bogus, bogusRef).ok());
  farm::ReportReply completion;
  farm::CompleteRequest request;
  request.set_attempt_id(attempt);
  *request.mutable_output() = bogusRef;
  const grpc::Status completed = link.complete(request, completion);
  ASSERT_TRUE(completed.ok()) << completed.error_message();
  EXPECT_FALSE(completion.accepted());
  EXPECT_TRUE(contains(completion.reason(), "lease")) << completion.reason();
  farm::HeartbeatReply beat;
  ASSERT_TRUE(link.heartbeat(attempt, 0.9, beat).ok());
  EXPECT_FALSE(beat.keep_going());
  farm::ReportReply failure;
  farm::FailRequest late;
  late.set_attempt_id(attempt);
  late.set_reason("too late");
  ASSERT_TRUE(link.fail(late, failure).ok());
  EXPECT_FALSE(failure.accepted());
  farm::ReportReply lateTiles;
  ASSERT_TRUE(link.reportFollowUps(planted, lateTiles).ok());
  EXPECT_FALSE(lateTiles.accepted());
  EXPECT_EQ(db.integer("SELECT COUNT(*) FROM follow_ups"), 0);
  EXPECT_EQ(link.leaseInputs(peek).error_code(), grpc::StatusCode::FAILED_PRECONDITION);
  EXPECT_EQ(db.integer(attemptState), 3);
  EXPECT_EQ(db.integer("SELECT state FROM tasks WHERE id = " + std::to_string(task)), 1) << "task back to ready";
  EXPECT_EQ(db.integer("SELECT COUNT(*) FROM tasks WHERE output_sha = '" + bogusRef.sha256() + "'"), 0);

  // Real workers finish the shot, and the frame is exactly the local render.
  startWorker("w1");
  startWorker("w2");
  const farm::ShotSummary summary = waitForShot(id, 30s);
  ASSERT_EQ(summary.state(), farm::SHOT_DONE) << describe(summary);
  EXPECT_EQ(db.integer(attemptState), 3);
  EXPECT_EQ(db.integer("SELECT COUNT(*) FROM tasks WHERE output_sha = '" + bogusRef.sha256() + "'"), 0);
  EXPECT_EQ(db.integer("SELECT COUNT(*) FROM attempts a JOIN workers w ON w.id = a.worker_id WHERE a.task_id = " +
                       std::to_string(task) + " AND a.state = 1 AND w.name != 'silent'"),
            1);

  const fs::path fetched = fetchFrames(id, "fetched");
  expectSameFrames(fetched, renderLocally(spec), spec);
}

}  // namespace
}  // namespace pathfarm::farmtest
