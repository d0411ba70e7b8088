#pragma once
// The filtering pipelines' tasks (d, du, di, dui; scheduler/planner.h), each a function of
// its decoded inputs: the postproc library does the work, these functions pick the inputs,
// join the results into the task's output frame and say which pixels need re-rendering.
// Channel layout of the intermediate chunks: docs/farm.md, "Task graphs".
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "image/exr_io.h"
#include "image/frame_image.h"
#include "pathfarm/worker_service.pb.h"
#include "worker/scratch_file.h"

namespace pathfarm::farm {

// What a task reads of an input: the channels `keep` accepts (every one without it), of
// rows firstRow .. endRow - 1 (to the last row when endRow is 0), with every attribute of
// the frame.
struct InputPart {
  ChannelFilter keep;
  int firstRow = 0, endRow = 0;
};

// One input chunk: what made it and its image. The image may be shared with the worker's
// decoded inputs (worker/decoded_inputs.h) and other tasks, so a task changes only what
// take() gives it. A worker's inputs are decoded when the task first asks for them, so that
// a task that reduces each frame as it gets it (dui's denoise, to half resolution) never
// holds its inputs whole at once.
struct TaskInput {
  TaskKind kind;
  TaskParams params;
  mutable std::shared_ptr<FrameImage> frame;  // shared: change only what take() gives
  // Makes `frame` when it is first asked for; empty when `frame` was given.
  mutable std::function<std::shared_ptr<FrameImage>()> decode = {};
  // Makes a part of the frame; empty: parts are taken from image().
  std::function<FrameImage(const InputPart&)> decodePart = {};
  // The channels its chunk stores as 16-bit floats (image/exr_io.h), from the chunk's
  // header; empty: none.
  std::function<std::vector<std::string>()> halfChannels = {};

  const FrameImage& image() const;
  // A part of the frame: copied from it when it is decoded already, else decoded alone
  // (decodePart), so that a task reading one component of a keyframe, or a window of
  // rows, of a frame too large for the worker's decoded inputs holds that part alone. The
  // input itself is left as it was.
  FrameImage part(const InputPart& wanted) const;
  // The image, to change: moved out when this input alone holds it (a frame too large for
  // the decoded inputs' budget: a 1080p keyframe of 150 channels is 1.2 GB, and copying it
  // would double a filter task's memory), else copied. The input is empty afterwards.
  FrameImage take();
};

struct TaskOutput {
  std::string chunk;                             // the output chunk's bytes, or
  std::shared_ptr<const ScratchFile> chunkFile;  // a file holding them (an assembled frame), or
  // a frame the worker writes into such a file a strip of rows at a time, so that a large
  // frame is never held beside its encoding,
  std::optional<FrameImage> frame;
  // or a frame of `joinedHeight` rows the worker writes from windows of rows, top to
  // bottom, each got from its function when its turn comes and let go once written: a join
  // of windows holds one at a time. The functions may read the task's inputs.
  std::vector<std::function<FrameImage()>> rowWindows;
  int joinedHeight = 0;
  // How `frame` or `rowWindows` is written: RLE for an intermediate chunk, ZIP for a frame
  // the shot keeps. An intermediate `frame` stores what halfPrecisionChannels
  // (worker/chunk_channels.h) allows as 16-bit floats; `rowWindows` store `halfChannels` so.
  ExrCompression compression = ExrCompression::Fast;
  ChannelFilter halfChannels = {};
  std::vector<TaskParams> followUps;      // render tiles to add to the shot
  std::map<std::string, double> metrics;  // figures for the shot's report
};

// Writes a task's `frame` or `rowWindows` (whichever it has) to `file` a strip of rows at a
// time, and lets go of it. A failed write is this worker's (std::runtime_error), not the
// task's input's; a window's function throws what it throws.
void writeOutputFrame(TaskOutput& output, const std::filesystem::path& file);
// Runs a step of writing a task's output file: an ExrError there is this worker's disk,
// not the task's input, so it becomes a std::runtime_error (a worker fault).
void writingOutput(const std::function<void()>& step);

// A keyframe denoised with its neighbouring keyframes (at half resolution when upsampling).
TaskOutput runDenoiseTask(const Lease& lease, std::vector<TaskInput>& inputs);
// The denoised keyframe upsampled under its full-resolution features; negative pixels are
// re-rendered.
TaskOutput runUpsampleTask(const Lease& lease, std::vector<TaskInput>& inputs);
// One component's irradiance flow between two filtered keyframes.
TaskOutput runFlowTask(const Lease& lease, std::vector<TaskInput>& inputs);
// An in-between frame from its keyframes; its re-render mask becomes render tiles.
TaskOutput runInterpolateTask(const Lease& lease, std::vector<TaskInput>& inputs);
// A frame's final image: its stage output with the re-rendered pixels, denoised.
TaskOutput runCompositeTask(const Lease& lease, std::vector<TaskInput>& inputs);
// tgpt: the screened Poisson reconstruction of a window of gradient frames.
TaskOutput runPoissonWindowTask(const Lease& lease, std::vector<TaskInput>& inputs);
// tgpt: a frame blended (Hann weights) from the windows covering it, plus its direct emission.
TaskOutput runPoissonBlendTask(const Lease& lease, std::vector<TaskInput>& inputs);
// relMSE and temporal error of every stage of the evaluation frames against the reference.
TaskOutput runEvaluateTask(const Lease& lease, std::vector<TaskInput>& inputs);

}  // namespace pathfarm::farm
