// Messages of bounded size, however large the frame: a lease's inputs read in parts, and
// the re-render tiles a filter asks for sent in batches and staged until it completes.
#include "scheduler/farm_state.h"
#include "scheduler/farm_state_internal.h"

#include "contract/pipeline.h"

namespace pathfarm::farm {
namespace {

int64_t tilesPerFrame(const ShotSpec& spec) {
  const int64_t tile = std::max(1, spec.tile());
  return ((spec.width() + tile - 1) / tile) * ((spec.height() + tile - 1) / tile);
}

// Why a follow-up of a task of `frame` cannot be a render tile of the shot; "" if it can.
std::string refusalOfFollowUp(const TaskParams& params, int64_t frame, const ShotSpec& spec) {
  if (params.role() != ROLE_RERENDER) return "a follow-up tile is not a re-render";
  if (params.frame() != frame) return "a follow-up tile is not of the task's frame";
  if (params.spp() != rerenderSppOf(spec))
    return "a follow-up tile asks for " + std::to_string(params.spp()) + " samples, not the shot's re-render's " +
           std::to_string(rerenderSppOf(spec));
  const PixelWindow& w = params.window();
  if (w.x0() < 0 || w.y0() < 0 || w.x1() > spec.width() || w.y1() > spec.height() || w.x0() >= w.x1() ||
      w.y0() >= w.y1())
    return "a follow-up tile's window is not inside the frame";
  if (w.x1() - w.x0() > spec.tile() || w.y1() - w.y0() > spec.tile())
    return "a follow-up tile's window is larger than the shot's tiles";
  const size_t area = static_cast<size_t>(w.x1() - w.x0()) * static_cast<size_t>(w.y1() - w.y0());
  if (!params.pixel_mask().empty() && params.pixel_mask().size() != area)
    return "a follow-up tile's pixel mask does not have its window's size";
  return {};
}

// Whether a composite reads a re-render tile: a composite of the whole frame reads every
// one, a composite of a window those within kCompositeHalo of its rows.
bool readsTile(const TaskParams& composite, const PixelWindow& tile) {
  if (!composite.has_window()) return true;
  const PixelWindow& rows = composite.window();
  return tile.y1() > rows.y0() - kCompositeHalo && tile.y0() < rows.y1() + kCompositeHalo;
}

}  // namespace

int64_t FarmState::inputCount(int64_t taskId) {
  Statement& q = db_.query("SELECT COUNT(*) FROM task_deps WHERE task_id = ?1").bind(1, taskId);
  q.step();
  const int64_t count = q.integer(0);
  q.reset();
  return count;
}

std::optional<FarmState::InputsPart> FarmState::leaseInputs(int64_t attemptId, int64_t afterTaskId) {
  return transact([&]() -> std::optional<InputsPart> {
    const auto attempt = currentAttempt(attemptId);
    if (!attempt) return std::nullopt;
    InputsPart part;
    part.lastTaskId = appendInputs(attempt->taskId, afterTaskId, kInputsPerPart, part.part);
    return part;
  });
}

ReportReply FarmState::stageFollowUps(int64_t attemptId,
                                      const google::protobuf::RepeatedPtrField<TaskParams>& followUps) {
  return transact([&]() -> ReportReply {
    const auto attempt = currentAttempt(attemptId);
    if (!attempt) return refused(kStaleLease);
    ShotSpec spec;
    Statement& shot = db_.query("SELECT spec FROM shots WHERE id = ?1").bind(1, attempt->shotId);
    if (shot.step()) spec.ParseFromString(shot.blob(0));
    shot.reset();
    for (const TaskParams& params : followUps)
      if (const std::string refusal = refusalOfFollowUp(params, attempt->params.frame(), spec); !refusal.empty())
        return refused(refusal);
    Statement& staged = db_.query("SELECT COUNT(*) FROM follow_ups WHERE attempt_id = ?1").bind(1, attemptId);
    staged.step();
    const int64_t already = staged.integer(0);
    staged.reset();
    if (already + followUps.size() > tilesPerFrame(spec))
      return refused("more follow-up tiles than the frame has tiles (" + std::to_string(tilesPerFrame(spec)) + ")");
    for (const TaskParams& params : followUps)
      db_.query("INSERT INTO follow_ups (attempt_id, params) VALUES (?1, ?2)")
          .bind(1, attemptId)
          .bindBlob(2, params.SerializeAsString())
          .run();
    return accepted();
  });
}

void FarmState::addFollowUps(const AttemptRow& attempt, double now) {
  // The composite tasks waiting for the reporting task wait for the follow-ups too (a
  // composite of a window of rows, for those within its halo); they cannot be ready yet, as
  // the reporting task is not counted done until after this.
  std::vector<std::pair<int64_t, TaskParams>> composites;
  Statement& q = db_.query("SELECT t.id, t.params FROM task_deps d JOIN tasks t ON t.id = d.task_id "
                           "WHERE d.depends_on = ?1 AND t.kind = ?2");
  q.bind(1, attempt.taskId).bind(2, int64_t{TASK_COMPOSITE});
  while (q.step()) {
    TaskParams params;
    params.ParseFromString(q.blob(1));
    composites.emplace_back(q.integer(0), std::move(params));
  }
  q.reset();
  int64_t added = 0;
  Statement& staged = db_.query("SELECT params FROM follow_ups WHERE attempt_id = ?1 ORDER BY id").bind(1, attempt.id);
  while (staged.step()) {
    TaskParams params;
    params.ParseFromString(staged.blob(0));
    const int64_t id = insertTask(attempt.shotId, TASK_RENDER_TILE, params, 0, attempt.maxAttempts, false);
    db_.query("UPDATE tasks SET created_by = ?1 WHERE id = ?2").bind(1, attempt.taskId).bind(2, id).run();
    for (const auto& [composite, reader] : composites) {
      if (!readsTile(reader, params.window())) continue;
      db_.query("INSERT INTO task_deps (task_id, depends_on) VALUES (?1, ?2)").bind(1, composite).bind(2, id).run();
      db_.query("UPDATE tasks SET pending_deps = pending_deps + 1 WHERE id = ?1").bind(1, composite).run();
    }
    ++added;
  }
  staged.reset();
  if (added == 0) return;
  db_.query("DELETE FROM follow_ups WHERE attempt_id = ?1").bind(1, attempt.id).run();
  db_.query("UPDATE shots SET tasks_left = tasks_left + ?1 WHERE id = ?2").bind(1, added).bind(2, attempt.shotId).run();
  addEvent(attempt.shotId,
           describeTask(attempt.taskId, attempt.kind, attempt.params) + " asked for " + std::to_string(added) +
               " re-render tiles",
           now);
}

void FarmState::dropStaleFollowUps() {
  db_.query("DELETE FROM follow_ups WHERE attempt_id NOT IN (SELECT id FROM attempts WHERE state = ?1)")
      .bind(1, int64_t{kRunning})
      .run();
}

}  // namespace pathfarm::farm
