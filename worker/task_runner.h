#pragma once
// Runs one leased task with the renderer and postproc libraries and returns its output: a
// tile's EXR for render_tile, the frame's EXR file for assemble_frame
// (worker/assemble_frame.h), the filter tasks' chunks
// (worker/filter_tasks.h), the Metropolis tasks' (worker/metropolis_tasks.h), nothing
// for noop.
// Scenes and their built geometry are cached per shot, so the tiles of a shot pay for
// loading and BVH building once per worker; decoded input chunks are kept within a byte
// budget (worker/decoded_inputs.h), so a keyframe many tasks read is decoded once.
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
#include "worker/assemble_frame.h"
#include "worker/decoded_inputs.h"
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
  static constexpr uint64_t kDefaultDecodedInputBytes = 250'000'000;

  // Input chunks' bytes by digest (from a cache or the scheduler); throws on failure.
  using ChunkFetcher = std::function<std::string(const ChunkRef&)>;

  // Uploaded scenes are rebuilt under `scenesRoot` (worker/scene_files.h); assembled
  // frames are written to files in `outgoingRoot` (TaskOutput::chunkFile); decoded inputs
  // are kept up to `decodedInputBytes`.
  TaskRunner(int threads, std::filesystem::path scenesRoot, std::filesystem::path outgoingRoot,
             uint64_t decodedInputBytes = kDefaultDecodedInputBytes)
      : threads_(threads),
        scenesRoot_(std::move(scenesRoot)),
        outgoingRoot_(std::move(outgoingRoot)),
        decoded_(decodedInputBytes) {}
  ~TaskRunner();

  // `progress` receives 0..1; `abandon` turning true stops the task with TaskAbandoned.
  // Any other failure throws with a message for the scheduler's records. Inputs read in
  // place (an assembled frame's tiles) come from `files`; without it, from `fetch` through
  // scratch files.
  TaskOutput run(const Lease& lease, const ChunkFetcher& fetch, std::atomic<double>& progress,
                 const std::atomic<bool>& abandon, const ChunkFileFetcher& files = {});

 private:
  struct ShotRenderer;
  std::shared_ptr<ShotRenderer> rendererFor(const Lease& lease, const ChunkFetcher& fetch);
  TaskOutput assemble(const Lease& lease, const ChunkFetcher& fetch, const ChunkFileFetcher& files,
                      std::atomic<double>& progress);
  TaskOutput handOnGivenFrame(const Lease& lease, const ChunkFetcher& fetch);
  TaskOutput renderTile(const Lease& lease, const ChunkFetcher& fetch, std::atomic<double>& progress,
                        const std::atomic<bool>& abandon);
  TaskOutput renderGradientFrame(const Lease& lease, const ChunkFetcher& fetch, std::atomic<double>& progress,
                                 const std::atomic<bool>& abandon);
  TaskOutput renderGradientTile(const Lease& lease, const ChunkFetcher& fetch, std::atomic<double>& progress,
                                const std::atomic<bool>& abandon);
  TaskOutput joinGradientTiles(const Lease& lease, const ChunkFetcher& fetch, std::atomic<double>& progress);
  TaskOutput filter(const Lease& lease, const ChunkFetcher& fetch, const ChunkFileFetcher& files,
                    std::atomic<double>& progress);
  TaskOutput runMetropolis(const Lease& lease, const ChunkFetcher& fetch, std::atomic<double>& progress,
                           const std::atomic<bool>& abandon);
  // The lease's input chunks, fetched (with `files`, into the worker's cache), each decoded
  // when the task first asks for it; `progress` goes to 0.5 as they arrive.
  std::vector<TaskInput> inputsOf(const Lease& lease, const ChunkFetcher& fetch, std::atomic<double>& progress,
                                  const ChunkFileFetcher& files = {});
  // An input chunk's frame: made by `decode` and checked once, then kept in decoded_.
  std::shared_ptr<FrameImage> decodedInput(const ChunkRef& ref, const std::function<FrameImage()>& decode);
  // The part `wanted` names of the input chunk in `file` (TaskInput::part); `whole`
  // decodes the frame through the decoded inputs.
  FrameImage decodedPart(const ChunkRef& ref, const std::string& label, const std::filesystem::path& file,
                         const std::function<std::shared_ptr<FrameImage>()>& whole, const InputPart& wanted);

  int threads_;
  std::filesystem::path scenesRoot_;
  std::filesystem::path outgoingRoot_;
  DecodedInputs decoded_;
  std::mutex mutex_;
  std::vector<std::pair<int64_t, std::shared_ptr<ShotRenderer>>> renderers_;  // by shot id, recent first
};

}  // namespace pathfarm::farm
