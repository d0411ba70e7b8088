#pragma once
// Shared by FarmState's source files (farm_state*.cpp), not by its users: the
// transaction wrapper and the small conversions every query needs.
#include <mutex>
#include <string>
#include <type_traits>

#include "scheduler/farm_state.h"
#include "scheduler/schema.h"

namespace pathfarm::farm {

inline constexpr int kRunning = static_cast<int>(AttemptState::Running);

inline int64_t asInt(TaskState s) { return static_cast<int64_t>(s); }
inline int64_t asInt(AttemptState s) { return static_cast<int64_t>(s); }

inline bool isActive(ShotState state) { return state == SHOT_QUEUED || state == SHOT_RUNNING; }

// Tags as stored: ",a,b," (every tag between commas, so a lookup is one search), "" for none.
template <class Iterator>
std::string tagList(Iterator first, Iterator last) {
  std::string list;
  for (; first != last; ++first) list += "," + *first;
  return list.empty() ? list : list + ",";
}

inline constexpr const char* kStaleLease = "the lease is no longer current (expired, revoked or superseded)";

inline ReportReply refused(const std::string& reason) {
  ReportReply reply;
  reply.set_reason(reason);
  return reply;
}

inline ReportReply accepted() {
  ReportReply reply;
  reply.set_accepted(true);
  return reply;
}

// "task 12 (TASK_RENDER_TILE, frame 3, pixels [0,64)x[0,64))", for events.
inline std::string describeTask(int64_t taskId, TaskKind kind, const TaskParams& params) {
  std::string text = "task " + std::to_string(taskId) + " (" + TaskKind_Name(kind);
  if (kind != TASK_NOOP) text += ", frame " + std::to_string(params.frame());
  if (params.has_window()) {
    const PixelWindow& w = params.window();
    text += ", pixels [" + std::to_string(w.x0()) + "," + std::to_string(w.x1()) + ")x[" + std::to_string(w.y0()) +
            "," + std::to_string(w.y1()) + ")";
  }
  return text + ")";
}

// A running attempt with what its task needs to be judged (FarmState::currentAttempt).
struct FarmState::AttemptRow {
  int64_t id, taskId, shotId, workerId;
  TaskKind kind;
  int failures, maxAttempts, lost;
  TaskParams params;
};

template <class Body>
auto FarmState::transact(Body body) -> decltype(body()) {
  const std::lock_guard lock(mutex_);
  Transaction transaction(db_);
  if constexpr (std::is_void_v<decltype(body())>) {
    body();
    transaction.commit();
  } else {
    auto result = body();
    transaction.commit();
    return result;
  }
}

template <class Message>
int64_t FarmState::appendInputs(int64_t taskId, int64_t afterTaskId, int64_t limit, Message& message) {
  Statement& inputs = db_.query(
      "SELECT t.output_sha, c.size, t.params, t.kind, t.id FROM task_deps d JOIN tasks t ON t.id = d.depends_on "
      "JOIN chunks c ON c.sha256 = t.output_sha WHERE d.task_id = ?1 AND t.id > ?2 ORDER BY t.id LIMIT ?3");
  inputs.bind(1, taskId).bind(2, afterTaskId).bind(3, limit);
  int64_t last = 0;
  while (inputs.step()) {
    ChunkRef* ref = message.add_inputs();
    ref->set_sha256(inputs.text(0));
    ref->set_size(inputs.integer(1));
    message.add_input_params()->ParseFromString(inputs.blob(2));
    message.add_input_kinds(static_cast<TaskKind>(inputs.integer(3)));
    last = inputs.integer(4);
  }
  inputs.reset();
  return last;
}

}  // namespace pathfarm::farm
