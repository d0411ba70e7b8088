#include "scheduler/http/dashboard_json.h"

#include <cctype>

#include "contract/pipeline.h"
#include "scheduler/farm_names.h"

namespace pathfarm::farm {
namespace {

using nlohmann::json;

// The last events of a shot its page shows, and the last ones naming a task in its log.
constexpr size_t kShotEvents = 100;
constexpr size_t kTaskLogLines = 8;

json eventJson(const ShotEvent& event) { return {{"time", event.time()}, {"message", event.message()}}; }

// Whether the message names task `id` ("task 12 (render_tile, ...)", "requeued task 12:"),
// and not task 120.
bool namesTask(const std::string& message, int64_t id) {
  const std::string name = "task " + std::to_string(id);
  for (size_t at = message.find(name); at != std::string::npos; at = message.find(name, at + 1)) {
    const size_t end = at + name.size();
    if (end == message.size() || !std::isdigit(static_cast<unsigned char>(message[end]))) return true;
  }
  return false;
}

json attemptJson(const FarmState::AttemptDetail& a, double now) {
  const double end = a.finishedAt.value_or(now);
  return {{"id", a.id},
          {"worker_id", a.workerId},
          {"worker", a.workerName},
          {"state", attemptStateName(a.state)},
          {"leased_at", a.leasedAt},
          {"finished_at", a.finishedAt ? json(*a.finishedAt) : json(nullptr)},
          {"seconds", end - a.leasedAt},
          {"progress", a.progress},
          {"error", a.error},
          {"failure_class", a.failureClass},
          {"log_tail", a.logTail}};
}

json taskJson(const FarmState::TaskDetail& task, const std::vector<ShotEvent>& events, double now) {
  json attempts = json::array();
  for (const auto& a : task.attempts) attempts.push_back(attemptJson(a, now));
  json log = json::array();
  for (const ShotEvent& event : events)
    if (namesTask(event.message(), task.id)) log.push_back(eventJson(event));
  if (log.size() > kTaskLogLines) log.erase(log.begin(), log.end() - static_cast<std::ptrdiff_t>(kTaskLogLines));
  json window = nullptr;
  if (task.params.has_window()) {
    const PixelWindow& w = task.params.window();
    window = {w.x0(), w.y0(), w.x1(), w.y1()};
  }
  // The attempt that speaks for the task: the one running, or the one that finished last.
  const json last = attempts.empty() ? json(nullptr) : attempts.back();
  return {{"id", task.id},
          {"kind", lowerWithout(TaskKind_Name(task.kind), "TASK_")},
          {"frame", task.params.frame()},
          {"window", window},
          {"role", lowerWithout(TaskRole_Name(task.params.role()), "ROLE_")},
          {"state", taskStateName(task.state)},
          {"failures", task.failures},
          {"lost", task.lost},
          {"max_attempts", task.maxAttempts},
          {"core_seconds", task.coreSeconds},
          {"worker", last.is_null() ? json("") : last["worker"]},
          {"seconds", last.is_null() ? json(nullptr) : last["seconds"]},
          {"attempts", attempts},
          {"log", log}};
}

}  // namespace

json shotJson(const ShotSummary& s) {
  return {{"id", s.id()},
          {"name", s.name()},
          {"state", lowerWithout(ShotState_Name(s.state()), "SHOT_")},
          {"priority", s.priority()},
          {"tasks_total", s.tasks_total()},
          {"tasks_done", s.tasks_done()},
          {"tasks_running", s.tasks_running()},
          {"tasks_failed", s.tasks_failed()},
          {"frames_total", s.frames_total()},
          {"frames_done", s.frames_done()},
          {"elapsed_seconds", s.elapsed_seconds()},
          {"workers_busy", s.workers_busy()},
          {"attempts", s.attempts()},
          {"failure", s.failure()}};
}

json shotPageJson(const ShotReply& shot, const std::vector<std::pair<int64_t, ChunkRef>>& frames,
                  const std::vector<BlocklistEntry>& blocklist) {
  const ShotSpec& spec = shot.spec();
  json events = json::array();
  const int first = std::max(0, shot.events_size() - static_cast<int>(kShotEvents));
  for (int i = first; i < shot.events_size(); ++i) events.push_back(eventJson(shot.events(i)));
  json frameList = json::array();
  for (const auto& [frame, chunk] : frames)
    frameList.push_back({{"frame", frame}, {"sha256", chunk.sha256()}, {"bytes", chunk.size()}});
  return {{"summary", shotJson(shot.summary())},
          {"spec",
           {{"scene", spec.scene()},
            {"pipeline", pipelineLabel(spec.pipeline())},
            {"frame_start", spec.frame_start()},
            {"frame_end", spec.frame_end()},
            {"width", spec.width()},
            {"height", spec.height()},
            {"spp", spec.spp()},
            {"tile", spec.tile()},
            {"output", spec.output()}}},
          {"events", events},
          {"events_total", shot.events_size()},
          {"frames", frameList},
          {"blocklist", blocklistJson(blocklist)}};
}

json tasksJson(const FarmState::TaskPage& page, const std::vector<ShotEvent>& events, double now) {
  json tasks = json::array();
  for (const auto& task : page.tasks) tasks.push_back(taskJson(task, events, now));
  return {{"matching", page.matching}, {"tasks", tasks}};
}

json workersJson(const std::vector<WorkerInfo>& workers, const std::vector<FarmState::RunningTask>& running,
                 const std::vector<BlocklistEntry>& blocklist, double leaseSeconds, double now) {
  json list = json::array();
  for (const WorkerInfo& w : workers) {
    json tasks = json::array();
    for (const auto& r : running)
      if (r.workerId == w.id())
        tasks.push_back({{"shot_id", r.shotId},
                         {"task_id", r.taskId},
                         {"kind", lowerWithout(TaskKind_Name(r.kind), "TASK_")},
                         {"frame", r.frame},
                         {"progress", r.progress},
                         {"seconds", now - r.leasedAt}});
    // As /metrics counts workers: seen within two lease periods is alive.
    const char* state = w.busy() > 0 ? "busy" : w.seconds_since_seen() <= 2 * leaseSeconds ? "idle" : "gone";
    list.push_back({{"id", w.id()},
                    {"name", w.name()},
                    {"state", state},
                    {"slots", w.slots()},
                    {"busy", w.busy()},
                    {"seconds_since_seen", w.seconds_since_seen()},
                    {"last_seen", now - w.seconds_since_seen()},
                    {"tasks", tasks}});
  }
  return {{"workers", list}, {"blocklist", blocklistJson(blocklist)}, {"time", now}};
}

json blocklistJson(const std::vector<BlocklistEntry>& entries) {
  json list = json::array();
  for (const BlocklistEntry& e : entries)
    list.push_back({{"shot_id", e.shot_id()},
                    {"worker_id", e.worker_id()},
                    {"worker", e.worker_name()},
                    {"failures", e.failures()}});
  return list;
}

}  // namespace pathfarm::farm
