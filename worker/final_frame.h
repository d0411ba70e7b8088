#pragma once
// A shot's final frame, as the farm writes it (docs/farm.md, "Task graphs"): the beauty
// and every component's color, `rerender.Y` marking the re-rendered pixels, and the
// stage output's attributes with the pipeline and the re-render count. The composite
// task writes it, or for d, where nothing is re-rendered, the denoise task itself.
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "contract/pipeline.h"
#include "image/frame_image.h"
#include "worker/filter_tasks.h"

namespace pathfarm::farm {

// Whether a channel is one of a final frame's colors: `R`, `G`, `B` or `<component>.color.*`.
bool isFinalColorChannel(const std::string& name);
// Throws BadInput naming `label` unless `frame` has the beauty and every component's colors.
void requireFinalColors(const FrameImage& frame, const std::string& label);
// The final frame's colors and attributes, taken from a stage output.
FrameImage finalColorsOf(const FrameImage& staged);

// Adds `rerendered` (a byte per pixel, 1 = re-rendered) to `final` as `rerender.Y`.
void addRerenderMask(FrameImage& final, const std::vector<uint8_t>& rerendered);

// A final frame's record of its re-render: its attributes "pathfarm.rerender_pixels" and
// "pathfarm.pipeline", and the output's "rerender_pixels" metric.
void recordRerender(std::map<std::string, std::string>& attributes, size_t rerenderedPixels, Pipeline pipeline,
                    TaskOutput& output);

// `final` with `rerendered` added as `rerender.Y`, encoded for the shot's output, with its
// "rerender_pixels" metric.
TaskOutput finishedFinalFrame(FrameImage final, const std::vector<uint8_t>& rerendered, Pipeline pipeline);

}  // namespace pathfarm::farm
