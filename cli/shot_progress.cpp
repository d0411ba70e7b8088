#include "cli/shot_progress.h"

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <cstdio>
#include <string>

#include "client/pipeline_probe.h"

namespace pathfarm {
namespace {

std::string workersBusy(int count) { return std::to_string(count) + (count == 1 ? " worker busy" : " workers busy"); }

}  // namespace

std::string describeShot(const farm::ShotSummary& s) {
  char line[512];
  std::snprintf(line, sizeof line, "%lld %s %s: %lld/%lld tasks done, %lld running, %lld/%lld frames, %s, %.1f s",
                static_cast<long long>(s.id()), s.name().c_str(), farm::ShotState_Name(s.state()).c_str(),
                static_cast<long long>(s.tasks_done()), static_cast<long long>(s.tasks_total()),
                static_cast<long long>(s.tasks_running()), static_cast<long long>(s.frames_done()),
                static_cast<long long>(s.frames_total()), workersBusy(s.workers_busy()).c_str(), s.elapsed_seconds());
  std::string text = line;
  if (s.priority() != 0) text += ", priority " + std::to_string(s.priority());
  if (!s.failure().empty()) text += "\n  failure: " + s.failure();
  return text;
}

ShotProgress::~ShotProgress() {
  if (drawn_) std::fputc('\n', stderr);
}

void ShotProgress::update(const farm::ShotSummary& s) {
  if (!checked_) {
    terminal_ = isatty(STDERR_FILENO) != 0;
    checked_ = true;
  }
  const double fraction = s.tasks_total() > 0 ? static_cast<double>(s.tasks_done()) / s.tasks_total() : 0;
  const double remaining = fraction > 0 ? s.elapsed_seconds() * (1 - fraction) / fraction : 0;
  if (terminal_) {
    constexpr int kWidth = 30;
    const int filled = static_cast<int>(fraction * kWidth);
    std::fprintf(stderr, "\rshot %lld [%-*s] %lld/%lld tasks, %s, %.0fs elapsed, %.0fs left ",
                 static_cast<long long>(s.id()), kWidth, std::string(static_cast<size_t>(filled), '#').c_str(),
                 static_cast<long long>(s.tasks_done()), static_cast<long long>(s.tasks_total()),
                 workersBusy(s.workers_busy()).c_str(), s.elapsed_seconds(), remaining);
    std::fflush(stderr);
    drawn_ = true;
  } else if (s.elapsed_seconds() - lastLogged_ >= 2 || s.tasks_done() == s.tasks_total()) {
    spdlog::info("shot {}: {}/{} tasks, {}, {:.1f} s elapsed, {:.1f} s left", s.id(), s.tasks_done(), s.tasks_total(),
                 workersBusy(s.workers_busy()), s.elapsed_seconds(), remaining);
    lastLogged_ = s.elapsed_seconds();
  }
}

farm::ShotSpec withChosenPipeline(farm::FarmClient& client, const farm::ShotFile& file, farm::ShotSpec spec,
                                  const std::filesystem::path& probeFolder, const std::string& submitKey) {
  if (spec.pipeline() != farm::PIPELINE_AUTO) return spec;
  ShotProgress progress;
  return farm::choosePipeline(client, file, spec, probeFolder,
                              [&](const farm::ShotSummary& summary) { progress.update(summary); }, submitKey);
}

}  // namespace pathfarm
