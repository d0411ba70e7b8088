#include "worker/final_frame.h"

#include <algorithm>
#include <stdexcept>
#include <string_view>

#include "image/exr_io.h"
#include "postproc/filters/decomposed_frame.h"
#include "worker/failure_class.h"
#include "worker/filter_inputs.h"

namespace pathfarm::farm {

bool isFinalColorChannel(const std::string& name) {
  if (name == "R" || name == "G" || name == "B") return true;
  // <component>.color.<R|G|B>: component names hold no dot.
  const size_t dot = name.find('.');
  if (dot == std::string::npos) return false;
  const std::string_view rest = std::string_view(name).substr(dot);
  return rest == ".color.R" || rest == ".color.G" || rest == ".color.B";
}

void requireFinalColors(const FrameImage& frame, const std::string& label) {
  std::vector<std::string> wanted = {"R", "G", "B"};
  for (const std::string& component : decompositionComponents(frame))
    for (const char* c : {"R", "G", "B"}) wanted.push_back(component + ".color." + c);
  for (const std::string& name : wanted)
    if (!frame.hasChannel(name)) throw BadInput(label + " has no channel \"" + name + "\"");
}

FrameImage finalColorsOf(const FrameImage& staged) {
  requireFinalColors(staged, "the stage output");
  return partOf(staged, {isFinalColorChannel});
}

void addRerenderMask(FrameImage& final, const std::vector<uint8_t>& rerendered) {
  if (rerendered.size() != final.pixelCount())
    throw std::logic_error("addRerenderMask: the re-render mask does not have the frame's size");
  std::vector<float>& flagged = final.addChannel("rerender.Y");
  std::copy(rerendered.begin(), rerendered.end(), flagged.begin());
}

void recordRerender(std::map<std::string, std::string>& attributes, size_t rerenderedPixels, Pipeline pipeline,
                    TaskOutput& output) {
  attributes["pathfarm.rerender_pixels"] = std::to_string(rerenderedPixels);
  attributes["pathfarm.pipeline"] = pipelineName(pipeline);
  output.metrics["rerender_pixels"] = static_cast<double>(rerenderedPixels);
}

TaskOutput finishedFinalFrame(FrameImage final, const std::vector<uint8_t>& rerendered, Pipeline pipeline) {
  addRerenderMask(final, rerendered);
  TaskOutput output;
  recordRerender(final.attributes(), static_cast<size_t>(std::count(rerendered.begin(), rerendered.end(), 1)), pipeline,
                 output);
  output.chunk = encodeExr(final);
  return output;
}

}  // namespace pathfarm::farm
