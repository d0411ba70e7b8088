#include "worker/task_log.h"

#include <spdlog/sinks/base_sink.h>
#include <spdlog/spdlog.h>

namespace pathfarm::farm {
namespace {

thread_local TaskLog* capturing = nullptr;

// Formats a message (time, level, text) for the task log of the thread that logs it.
class TaskLogSink : public spdlog::sinks::base_sink<std::mutex> {
 protected:
  void sink_it_(const spdlog::details::log_msg& message) override {
    if (!capturing) return;
    spdlog::memory_buf_t formatted;
    formatter_->format(message, formatted);
    capturing->add(fmt::to_string(formatted));
  }
  void flush_() override {}
};

}  // namespace

TaskLog::Capture::Capture(TaskLog& log) : previous_(capturing) { capturing = &log; }

TaskLog::Capture::~Capture() { capturing = previous_; }

void TaskLog::add(std::string line) {
  if (line.empty() || line.back() != '\n') line += '\n';
  const std::lock_guard lock(mutex_);
  lines_.push_back(std::move(line));
  if (lines_.size() > kMaxLines) lines_.pop_front();
}

std::string TaskLog::tail() const {
  const std::lock_guard lock(mutex_);
  std::string text;
  for (const std::string& line : lines_) text += line;
  return text;
}

void installTaskLogSink() {
  static std::once_flag once;
  std::call_once(once, [] {
    auto sink = std::make_shared<TaskLogSink>();
    sink->set_pattern("[%H:%M:%S] %l %v");
    spdlog::default_logger()->sinks().push_back(std::move(sink));
  });
}

}  // namespace pathfarm::farm
