#pragma once
// A task's log tail: the lines the worker logs while it runs a task, from the threads that
// run it, kept (the last kMaxLines) to travel with the task's completion or failure, so the
// scheduler's dashboard shows what the worker said about that task.
#include <deque>
#include <mutex>
#include <string>

namespace pathfarm::farm {

class TaskLog {
 public:
  static constexpr size_t kMaxLines = 40;

  // While it lives, what this thread logs goes to `log` too (beside the worker's own log).
  class Capture {
   public:
    explicit Capture(TaskLog& log);
    ~Capture();
    Capture(const Capture&) = delete;
    Capture& operator=(const Capture&) = delete;

   private:
    TaskLog* previous_;
  };

  void add(std::string line);
  // The kept lines, oldest first, each ending in a newline.
  std::string tail() const;

 private:
  mutable std::mutex mutex_;
  std::deque<std::string> lines_;
};

// Adds, once per process, the spdlog sink that feeds capturing threads' task logs to the
// default logger. Call before the threads that log start.
void installTaskLogSink();

}  // namespace pathfarm::farm
