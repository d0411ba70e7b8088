#include "worker/final_frame.h"

#include <algorithm>
#include <stdexcept>

#include "image/exr_io.h"
#include "postproc/filters/decomposed_frame.h"

namespace pathfarm::farm {

FrameImage finalColorsOf(const FrameImage& staged) {
  FrameImage final(staged.width(), staged.height());
  for (const char* c : {"R", "G", "B"}) final.addChannel(c) = staged.channel(c);
  for (const std::string& component : decompositionComponents(staged))
    for (const char* c : {"R", "G", "B"}) {
      const std::string name = component + ".color." + c;
      final.addChannel(name) = staged.channel(name);
    }
  final.attributes() = staged.attributes();
  return final;
}

TaskOutput finishedFinalFrame(FrameImage final, const std::vector<uint8_t>& rerendered, Pipeline pipeline) {
  if (rerendered.size() != final.pixelCount())
    throw std::logic_error("finishedFinalFrame: the re-render mask does not have the frame's size");
  std::vector<float>& flagged = final.addChannel("rerender.Y");
  std::copy(rerendered.begin(), rerendered.end(), flagged.begin());
  const auto count = static_cast<size_t>(std::count(rerendered.begin(), rerendered.end(), 1));
  final.attributes()["pathfarm.rerender_pixels"] = std::to_string(count);
  final.attributes()["pathfarm.pipeline"] = pipelineName(pipeline);
  TaskOutput output;
  output.chunk = encodeExr(final);
  output.metrics["rerender_pixels"] = static_cast<double>(count);
  return output;
}

}  // namespace pathfarm::farm
