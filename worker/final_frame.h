#pragma once
// A shot's final frame, as the farm writes it (docs/farm.md, "Task graphs"): the beauty
// and every component's color, `rerender.Y` marking the re-rendered pixels, and the
// stage output's attributes with the pipeline and the re-render count. The composite
// task writes it, or for d, where nothing is re-rendered, the denoise task itself.
#include <cstdint>
#include <string>
#include <vector>

#include "contract/pipeline.h"
#include "image/frame_image.h"
#include "worker/filter_tasks.h"

namespace pathfarm::farm {

// The final frame's colors and attributes, taken from a stage output.
FrameImage finalColorsOf(const FrameImage& staged);

// `final` with `rerendered` (a byte per pixel, 1 = re-rendered) added as `rerender.Y`,
// encoded for the shot's output, with its "rerender_pixels" metric.
TaskOutput finishedFinalFrame(FrameImage final, const std::vector<uint8_t>& rerendered, Pipeline pipeline);

}  // namespace pathfarm::farm
