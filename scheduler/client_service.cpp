#include <chrono>
#include <thread>

#include "proto/wire/chunk_transfer.h"
#include "scheduler/service_chunks.h"
#include "scheduler/service_guard.h"
#include "scheduler/shot_report.h"

namespace pathfarm::farm {
namespace {

// The evaluation's chunk is its contact sheet (worker/evaluate_task.cpp), or a line of text
// when it had no final frame to show.
bool isPng(const std::string& bytes) { return bytes.rfind("\x89PNG", 0) == 0; }

}  // namespace

grpc::Status ClientServiceImpl::Submit(grpc::ServerContext* context, const SubmitRequest* request,
                                       SubmitReply* reply) {
  return guarded(c_, context, [&] {
    if (const std::string problem = inputProblem(request->spec()); !problem.empty())
      return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, problem);
    const auto plan = planShotWithin(request->spec(), c_.limits);
    reply->set_shot_id(c_.state.submit(request->spec(), plan, farmClockSeconds(), request->submit_key()));
    c_.signal.notify();
    return grpc::Status::OK;
  });
}

grpc::Status ClientServiceImpl::ListShots(grpc::ServerContext* context, const ListShotsRequest*,
                                          ListShotsReply* reply) {
  return guarded(c_, context, [&] {
    for (ShotSummary& s : c_.state.shots(farmClockSeconds())) *reply->add_shots() = std::move(s);
    return grpc::Status::OK;
  });
}

grpc::Status ClientServiceImpl::GetShot(grpc::ServerContext* context, const ShotRequest* request, ShotReply* reply) {
  return guarded(c_, context, [&] {
    *reply = c_.state.shot(request->shot_id(), farmClockSeconds());
    return grpc::Status::OK;
  });
}

grpc::Status ClientServiceImpl::GetReport(grpc::ServerContext* context, const ShotRequest* request,
                                          ShotReport* reply) {
  return guarded(c_, context, [&] {
    const ShotSummary summary = c_.state.summary(request->shot_id(), farmClockSeconds());
    const auto [spec, tasks] = c_.state.taskRecords(request->shot_id());
    *reply = buildReport(summary, spec, tasks);
    for (const TaskRecord& task : tasks)
      if (task.kind == TASK_EVALUATE && task.done)
        if (const auto sheet = c_.store.get(task.outputSha); sheet && isPng(*sheet)) reply->set_contact_sheet_png(*sheet);
    return grpc::Status::OK;
  });
}

grpc::Status ClientServiceImpl::WatchShot(grpc::ServerContext* context, const ShotRequest* request,
                                          grpc::ServerWriter<ShotSummary>* writer) {
  return guarded(c_, context, [&] {
    std::string last;
    uint64_t seen = c_.signal.generation();
    for (;;) {
      const ShotSummary summary = c_.state.summary(request->shot_id(), farmClockSeconds());
      // Elapsed time changes every call: compare what matters, but still send a beat
      // now and then so the client's clock keeps moving.
      ShotSummary comparable = summary;
      comparable.clear_elapsed_seconds();
      const std::string key = comparable.SerializeAsString();
      if (key != last || isFinished(summary.state())) {
        if (!writer->Write(summary)) return grpc::Status(grpc::StatusCode::CANCELLED, "the watcher went away");
        last = key;
      }
      if (isFinished(summary.state())) return grpc::Status::OK;
      const auto cancelled = [&] { return context->IsCancelled(); };
      if (cancelled()) return grpc::Status(grpc::StatusCode::CANCELLED, "the watcher went away");
      // At most ten summaries a second: a busy farm changes far more often than that, and
      // each summary reads the whole shot. A watcher that left stops holding the thread.
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
      if (cancelled()) return grpc::Status(grpc::StatusCode::CANCELLED, "the watcher went away");
      seen = c_.signal.waitFor(seen, std::chrono::milliseconds(400));
    }
  });
}

template <class Change>
grpc::Status ClientServiceImpl::controlShot(grpc::ServerContext* context, const ShotRequest* request,
                                            ControlReply* reply, Change change) {
  return guarded(c_, context, [&] {
    *reply->mutable_summary() = (c_.state.*change)(request->shot_id(), farmClockSeconds());
    c_.signal.notify();
    return grpc::Status::OK;
  });
}

grpc::Status ClientServiceImpl::CancelShot(grpc::ServerContext* context, const ShotRequest* request,
                                           ControlReply* reply) {
  return controlShot(context, request, reply, &FarmState::cancel);
}

grpc::Status ClientServiceImpl::PauseShot(grpc::ServerContext* context, const ShotRequest* request,
                                          ControlReply* reply) {
  return controlShot(context, request, reply, &FarmState::pause);
}

grpc::Status ClientServiceImpl::ResumeShot(grpc::ServerContext* context, const ShotRequest* request,
                                           ControlReply* reply) {
  return controlShot(context, request, reply, &FarmState::resume);
}

grpc::Status ClientServiceImpl::RetryShot(grpc::ServerContext* context, const ShotRequest* request,
                                          ControlReply* reply) {
  return controlShot(context, request, reply, &FarmState::retry);
}

grpc::Status ClientServiceImpl::FetchOutputs(grpc::ServerContext* context, const ShotRequest* request,
                                             grpc::ServerWriter<OutputPart>* writer) {
  return guarded(c_, context, [&] {
    c_.state.summary(request->shot_id(), farmClockSeconds());  // NOT_FOUND for an unknown shot
    const auto frames = request->references() ? c_.state.references(request->shot_id())
                                              : c_.state.outputs(request->shot_id());
    for (const auto& [frame, ref] : frames) {
      // Adapts the output stream to sendStoredChunk's Write(ChunkPart).
      struct FramePartWriter {
        grpc::ServerWriter<OutputPart>* writer;
        int64_t frame;
        bool Write(const ChunkPart& part) {
          OutputPart out;
          out.set_frame(frame);
          *out.mutable_part() = part;
          return writer->Write(out);
        }
      } frameWriter{writer, frame};
      const StoredSend sent = sendStoredChunk(frameWriter, c_.store, ref.sha256());
      if (sent == StoredSend::ReaderGone) return grpc::Status(grpc::StatusCode::CANCELLED, "the reader went away");
      if (sent == StoredSend::Absent) {
        const grpc::Status lost = lostChunk(c_, ref.sha256());
        return grpc::Status(grpc::StatusCode::DATA_LOSS, "frame " + std::to_string(frame) + ": " +
                                                             lost.error_message() + "; fetch again when the shot is done");
      }
    }
    return grpc::Status::OK;
  });
}

grpc::Status ClientServiceImpl::ListWorkers(grpc::ServerContext* context, const ListWorkersRequest*,
                                            ListWorkersReply* reply) {
  return guarded(c_, context, [&] {
    for (WorkerInfo& w : c_.state.workers(farmClockSeconds())) *reply->add_workers() = std::move(w);
    return grpc::Status::OK;
  });
}

grpc::Status ClientServiceImpl::SetPriority(grpc::ServerContext* context, const PriorityRequest* request,
                                            ControlReply* reply) {
  return guarded(c_, context, [&] {
    *reply->mutable_summary() = c_.state.setPriority(request->shot_id(), request->priority(), farmClockSeconds());
    c_.signal.notify();
    return grpc::Status::OK;
  });
}

grpc::Status ClientServiceImpl::Requeue(grpc::ServerContext* context, const RequeueRequest* request,
                                        ControlReply* reply) {
  return guarded(c_, context, [&] {
    const double now = farmClockSeconds();
    switch (request->what_case()) {
      case RequeueRequest::kTaskId:
        *reply->mutable_summary() = c_.state.requeueTask(request->shot_id(), request->task_id(), now);
        break;
      case RequeueRequest::kFrame:
        *reply->mutable_summary() = c_.state.requeueFrame(request->shot_id(), request->frame(), now);
        break;
      case RequeueRequest::WHAT_NOT_SET:
        return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, "requeue: name a task or a frame");
    }
    c_.signal.notify();
    return grpc::Status::OK;
  });
}

grpc::Status ClientServiceImpl::ListBlocklist(grpc::ServerContext* context, const BlocklistRequest* request,
                                              BlocklistReply* reply) {
  return guarded(c_, context, [&] {
    for (BlocklistEntry& e : c_.state.blocklist(request->shot_id())) *reply->add_entries() = std::move(e);
    return grpc::Status::OK;
  });
}

grpc::Status ClientServiceImpl::ClearBlocklist(grpc::ServerContext* context, const BlocklistRequest* request,
                                               BlocklistReply* reply) {
  return guarded(c_, context, [&] {
    c_.state.clearBlocklist(request->shot_id(), request->worker_id(), farmClockSeconds());
    for (BlocklistEntry& e : c_.state.blocklist(request->shot_id())) *reply->add_entries() = std::move(e);
    c_.signal.notify();
    return grpc::Status::OK;
  });
}

}  // namespace pathfarm::farm
