#pragma once
// Helpers the filter tasks share: finding inputs, motion fields in chunks, and turning a
// re-render mask into render tiles.
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "contract/pipeline.h"
#include "postproc/filters/warp.h"
#include "worker/filter_tasks.h"

namespace pathfarm::farm {

// The upsampling pipelines' keyframes are denoised at 1 / kUpsampleFactor of the shot's
// resolution (in each dimension) and upsampled back.
inline constexpr int kUpsampleFactor = 2;

// The first input `matches` accepts; throws std::runtime_error naming `what` when none does.
const TaskInput& findInput(const std::vector<TaskInput>& inputs, const std::function<bool(const TaskInput&)>& matches,
                           const std::string& what);
// The output of `kind` for `frame`, as findInput; the mutable one for TaskInput::take.
const TaskInput& inputOf(const std::vector<TaskInput>& inputs, TaskKind kind, int64_t frame);
TaskInput& inputOf(std::vector<TaskInput>& inputs, TaskKind kind, int64_t frame);
// A keyframe's filtered frame (upsample, else denoise output) for `frame`.
const TaskInput& filteredKeyframe(const std::vector<TaskInput>& inputs, int64_t frame);
TaskInput& filteredKeyframe(std::vector<TaskInput>& inputs, int64_t frame);

// Whether a channel is frame-wide: the beauty `R`, `G`, `B` or `<buffer>.<channel>`, not a
// component's `<component>.<buffer>.<channel>`.
bool isFrameWideChannel(const std::string& name);

// The part of `frame` that `wanted` names, with its attributes; rows outside the frame
// are BadInput.
FrameImage partOf(const FrameImage& frame, const InputPart& wanted);

// The channels every one of `inputs` stores as 16-bit floats (TaskInput::halfChannels):
// those a frame joined from them can store so and still hold their values.
ChannelFilter halfInEvery(const std::vector<TaskInput*>& inputs);

// A render (`input`, of width x height) without its directly seen light
// (takeDirectEmission), box-downsampled by `factor` (boxDownsample), read a strip of rows
// at a time: a 1080p keyframe's render is more than a gigabyte whole. Both steps are per
// pixel and per block, so the bits are those of the whole frame reduced at once.
// A window of rows (`rows`, full-resolution rows, whole blocks) reduces to those rows / factor.
FrameImage reducedWithoutLight(const TaskInput& input, int width, int height, int factor, const InputPart& rows = {});

// Pastes a filter's output over the frame whose features it was given, with the filter's
// record of what it did (its attributes named `record*`, e.g. pathfarm.denoise_skipped):
// FrameImage::paste moves pixels only.
void pasteFiltered(const FrameImage& filtered, const std::string& record, FrameImage& frame);

// The rows of its frame a filter task computes: its window's (whole rows, else BadInput
// naming `what`, e.g. "the upsample"), or every row without a window.
RowWindow rowsOf(const Lease& lease, const std::string& what);

// The join of a frame filtered in windows of rows (a filter task per window, and the
// frame's task of the same kind joining them; contract/pipeline.h, filterWindowsOf): its
// inputs, each a window of the lease's frame, must cover the frame's rows once each, whole
// rows, else BadInput naming `what` ("upsamples"). Returns their `rerender.Y` flags as the
// frame's mask (a byte per pixel) and their attributes, top to bottom, read before
// anything else, and sets `output` to write
// the windows top to bottom, each taken from its input when its turn comes, checked by
// `check` (when given) and to have the first window's channels (whose attributes the frame takes).
// A denoise's windows differ in two ways (JoinedFrame): they flag nothing, so hold no
// `rerender.Y`, and dui's are of the frame at half resolution (the windows' rows / factor).
struct JoinedFrame {
  bool flagged = true;
  int factor = 1;
};
struct JoinedWindows {
  std::vector<uint8_t> mask;
  std::vector<std::map<std::string, std::string>> attributes;
};
JoinedWindows joinRowWindows(const Lease& lease, std::vector<TaskInput>& inputs, const std::string& what,
                                    const std::function<void(const FrameImage&)>& check, TaskOutput& output,
                                    JoinedFrame joined = {});

// The counts `names` of a join's windows' attributes, each summed over the windows;
// BadInput naming `what` ("the denoise of frame 4") when a window's is not a count.
std::map<std::string, std::string> summedCounts(const JoinedWindows& windows, const std::vector<std::string>& names,
                                                const std::string& what);

// Adds `attributes` to the frame a join writes (it takes its first window's attributes).
void addJoinedAttributes(TaskOutput& output, std::map<std::string, std::string> attributes);

// Whether the lease is the join of its frame's windows: a task without a window whose
// inputs include tasks of its own kind.
bool joinsWindows(const Lease& lease, const std::vector<TaskInput>& inputs);
// A join whose frame goes on to other filters (an upsample's, an interpolation's): the
// windows written a window at a time, and the re-render of every pixel they flagged.
TaskOutput joinedWithRerender(const Lease& lease, std::vector<TaskInput>& inputs, const std::string& what);

// A motion field stored as `<name>.X`, `<name>.Y`, `<name>.valid`.
void writeMotionField(FrameImage& image, const std::string& name, const MotionField& field);
MotionField readMotionField(const FrameImage& image, const std::string& name);

// Groups the flagged pixels of a frame (`mask`, one byte per pixel) into the shot's tiles:
// one render task per tile with a flagged pixel, at rerenderSppOf(spec), rendering just those
// pixels. Adds "rerender_pixels" and "pixels" to `output.metrics`.
void requestRerender(const ShotSpec& spec, int64_t frame, const std::vector<uint8_t>& mask, TaskOutput& output);

}  // namespace pathfarm::farm
