// Upsampling of keyframes (worker/filter_tasks.h).
#include <algorithm>
#include <stdexcept>
#include <string>

#include "contract/pipeline.h"
#include "image/exr_io.h"
#include "postproc/filters/component_upsampler.h"
#include "postproc/filters/decomposed_frame.h"
#include "postproc/filters/guided_upsample.h"
#include "postproc/interpolation/caustic_check.h"
#include "worker/chunk_channels.h"
#include "postproc/filters/direct_emission.h"
#include "worker/failure_class.h"
#include "worker/filter_inputs.h"
#include "worker/final_frame.h"

namespace pathfarm::farm {

TaskOutput runUpsampleTask(const Lease& lease, std::vector<TaskInput>& inputs) {
  // The join of a keyframe upsampled in windows writes it a window at a time, never whole.
  if (joinsWindows(lease, inputs)) return joinedWithRerender(lease, inputs, "upsamples");
  const int64_t frame = lease.params().frame();
  const int width = lease.spec().width(), height = lease.spec().height();
  const FilteringStages stages = stagesOf(lease.spec().pipeline());
  const RowWindow rows = rowsOf(lease, "the upsample");
  const FrameRows wanted{rows.first, rows.end};
  UpsampleSettings settings;
  settings.guided.factor = kUpsampleFactor;
  // The rows the filters read around the wanted ones: the guided filter's strips and
  // windows, which reach farther than the checks of the render's light below.
  const FrameRows reads = guidedUpsampleReads(wanted, height, settings.guided);
  const int checksReach = std::max(causticCheckReach({}), kLightEdgeReach);
  if ((reads.first > 0 && wanted.first - reads.first < checksReach) ||
      (reads.end < height && reads.end - wanted.end < checksReach))
    throw std::logic_error("the upsample's checks reach beyond the rows the guided filter reads");
  settings.guided.firstRow = reads.first;
  settings.guided.onlyFirst = wanted.first;
  settings.guided.onlyEnd = wanted.end;
  const FrameImage low = inputOf(inputs, TASK_DENOISE, frame)
                             .part({{}, reads.first / kUpsampleFactor, reads.end / kUpsampleFactor});
  FrameImage high = inputOf(inputs, TASK_ASSEMBLE_FRAME, frame)
                        .part({[&](const std::string& name) { return upsampleReads(name, stages); }, reads.first,
                               reads.end});
  // A moving caustic spread by the half-resolution filtering is rendered again at full spp.
  // Without the check's noise bound, which is for the few samples of an in-between frame's
  // feature render: a keyframe's errors reach every frame interpolated from it, and with
  // the bound the dolly's error rose by a fifth (docs/performance.md).
  CausticCheckSettings causticCheck;
  causticCheck.z = 0.0f;
  const std::vector<uint8_t> caustics = movingCausticPixels(high, causticCheck);
  // The directly seen light is added back unfiltered from the keyframe's own render, which
  // has a quarter of the shot's samples: where it has an edge, that render's noise shows (a
  // pixel a lamp covers in part; a glossy highlight, whose light a rough mirror scatters at
  // random), so those pixels are rendered again at the shot's spp, as in an interpolated frame.
  const std::vector<uint8_t> lightEdges = directLightEdges(directEmissionOf(high), high);
  const FrameImage emission = takeDirectEmission(high);
  pasteFiltered(upsampleFrame(low, high, settings), "pathfarm.upsample", high);
  addDirectEmission(high, emission);
  if (wanted.first != reads.first || wanted.end != reads.end)
    high = high.crop(0, wanted.first - reads.first, width, wanted.end - wanted.first);
  std::vector<float>& flagged = high.channel("rerender.Y");
  std::vector<uint8_t> mask(flagged.size());
  const size_t skipped = static_cast<size_t>(wanted.first - reads.first) * static_cast<size_t>(width);
  size_t causticPixels = 0, edgePixels = 0;
  for (size_t p = 0; p < mask.size(); ++p) {
    causticPixels += caustics[skipped + p];
    edgePixels += lightEdges[skipped + p];
    if (caustics[skipped + p] || lightEdges[skipped + p]) flagged[p] = 1.0f;
    mask[p] = flagged[p] > 0.5f ? 1 : 0;
  }
  TaskOutput output;
  // A window's flags go to the re-render with the frame's, from the join.
  if (!lease.params().has_window()) requestRerender(lease.spec(), frame, mask, output);
  output.metrics["rerender_moving_caustics"] = static_cast<double>(causticPixels);
  output.metrics["rerender_light_edges"] = static_cast<double>(edgePixels);
  keepReadChannels(ChunkContent::FilteredKeyframe, stages, high);
  output.frame = std::move(high);
  return output;
}

}  // namespace pathfarm::farm
