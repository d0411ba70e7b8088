#pragma once
// Runs one leased task with the renderer and postproc libraries and returns its output: a
// tile's EXR for render_tile, the frame's EXR for assemble_frame, the filter tasks' chunks
// (worker/filter_tasks.h), the Metropolis tasks' (worker/metropolis_tasks.h), nothing
// for noop.
// Scenes and their built geometry are cached per shot, so the tiles of a shot pay for
// loading and BVH building once per worker.
#include <atomic>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "pathfarm/worker_service.pb.h"
#include "worker/filter_tasks.h"

namespace pathfarm {
class FrameRenderer;
struct Scene;
}  // namespace pathfarm

namespace pathfarm::farm {

// Thrown out of a running task when its lease is gone and the work is wasted.
class TaskAbandoned : public std::runtime_error {
 public:
  TaskAbandoned() : std::runtime_error("the lease was lost; task abandoned") {}
};

class TaskRunner {
 public:
  // Input chunks' bytes by digest (from a cache or the scheduler); throws on failure.
  using ChunkFetcher = std::function<std::string(const ChunkRef&)>;

  // Uploaded scenes are rebuilt under `scenesRoot` (worker/scene_files.h).
  TaskRunner(int threads, std::filesystem::path scenesRoot) : threads_(threads), scenesRoot_(std::move(scenesRoot)) {}
  ~TaskRunner();

  // `progress` receives 0..1; `abandon` turning true stops the task with TaskAbandoned.
  // Any other failure throws with a message for the scheduler's records.
  TaskOutput run(const Lease& lease, const ChunkFetcher& fetch, std::atomic<double>& progress,
                 const std::atomic<bool>& abandon);

 private:
  struct ShotRenderer;
  std::shared_ptr<ShotRenderer> rendererFor(const Lease& lease, const ChunkFetcher& fetch);
  TaskOutput renderTile(const Lease& lease, const ChunkFetcher& fetch, std::atomic<double>& progress,
                        const std::atomic<bool>& abandon);
  std::string assembleFrame(const Lease& lease, const ChunkFetcher& fetch, std::atomic<double>& progress);
  TaskOutput renderGradientFrame(const Lease& lease, const ChunkFetcher& fetch, std::atomic<double>& progress,
                                 const std::atomic<bool>& abandon);
  TaskOutput filter(const Lease& lease, const ChunkFetcher& fetch, std::atomic<double>& progress);
  TaskOutput runMetropolis(const Lease& lease, const ChunkFetcher& fetch, std::atomic<double>& progress,
                           const std::atomic<bool>& abandon);
  // The lease's input chunks, decoded; `progress` goes to 0.5 as they arrive.
  static std::vector<TaskInput> inputsOf(const Lease& lease, const ChunkFetcher& fetch, std::atomic<double>& progress);

  int threads_;
  std::filesystem::path scenesRoot_;
  std::mutex mutex_;
  std::vector<std::pair<int64_t, std::shared_ptr<ShotRenderer>>> renderers_;  // by shot id, recent first
};

}  // namespace pathfarm::farm
