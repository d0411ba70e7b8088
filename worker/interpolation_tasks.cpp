// Irradiance flow and frame interpolation between two keyframes (worker/filter_tasks.h).
#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <mutex>

#include "image/exr_io.h"
#include "postproc/filters/decomposed_frame.h"
#include "postproc/interpolation/caustic_check.h"
#include "postproc/interpolation/feature_check.h"
#include "postproc/interpolation/frame_interpolation.h"
#include "postproc/interpolation/radiance_check.h"
#include "worker/direct_emission.h"
#include "worker/failure_class.h"
#include "worker/filter_inputs.h"

namespace pathfarm::farm {
namespace {

// A component's motion between the keyframes (the frame-wide one for ""): forward from
// k0's motion vectors, backward from k1's, which reach each other (planner.h).
ComponentMotion keyframeMotion(const FrameImage& k0, const FrameImage& k1, const std::string& layer) {
  const std::string prefix = layer.empty() ? "" : layer + ".";
  return ComponentMotion(motionTowards(k0, NeighbourFrame::Next, prefix, "keyframe 0"),
                         motionTowards(k1, NeighbourFrame::Previous, prefix, "keyframe 1"));
}

bool isZero(const std::vector<float>& values) {
  return std::all_of(values.begin(), values.end(), [](float v) { return v == 0.0f; });
}

bool componentIsEmpty(const FrameImage& frame, const std::string& component) {
  for (const char* c : {"R", "G", "B"})
    if (!isZero(frame.channel(component + ".irradiance." + c))) return false;
  return true;
}

}  // namespace

TaskOutput runFlowTask(const Lease& lease, std::vector<TaskInput>& inputs) {
  const TaskParams& params = lease.params();
  const std::string& component = params.component();
  // The component's channels alone: a 1080p keyframe's others are gigabytes.
  const auto ofComponent = [&](const std::string& name) { return name.rfind(component + ".", 0) == 0; };
  const FrameImage k0 = filteredKeyframe(inputs, params.keyframe_before()).part({ofComponent});
  const FrameImage k1 = filteredKeyframe(inputs, params.keyframe_after()).part({ofComponent});
  const std::vector<std::string> components = decompositionComponents(k0);
  if (component.empty() || std::find(components.begin(), components.end(), component) == components.end())
    throw BadInput("the keyframes have no component " + component);

  ComponentMotions motions;
  motions.components[component] = keyframeMotion(k0, k1, component);
  FrameImage chunk(k0.width(), k0.height());
  // A component both keyframes lack has nothing to track: its (absent) flow is invalid
  // everywhere and interpolation falls back to the primary motion.
  if (componentIsEmpty(k0, component) && componentIsEmpty(k1, component)) {
    ComponentMotion& motion = motions.components[component];
    motion.irradianceForward = MotionField{k0.width(), k0.height(), std::vector<float>(k0.pixelCount(), 0.0f),
                                           std::vector<float>(k0.pixelCount(), 0.0f),
                                           std::vector<float>(k0.pixelCount(), 0.0f)};
    motion.irradianceBackward = motion.irradianceForward;
    chunk.attributes()["pathfarm.flow"] = "skipped: the component is empty in both keyframes";
  } else {
    addIrradianceFlow(motions, k0, k1, FlowSettings{});
    chunk.attributes()["pathfarm.flow"] = "irradiance flow, log domain, bootstrapped by the primary motion";
  }
  const ComponentMotion& motion = motions.components.at(component);
  writeMotionField(chunk, component + ".irradiance_forward", motion.irradianceForward);
  writeMotionField(chunk, component + ".irradiance_backward", motion.irradianceBackward);
  TaskOutput output;
  output.chunk = encodeExr(chunk, ExrCompression::Fast);
  return output;
}

TaskOutput runInterpolateTask(const Lease& lease, std::vector<TaskInput>& inputs) {
  const TaskParams& params = lease.params();
  const int64_t before = params.keyframe_before(), after = params.keyframe_after();
  const std::array<const TaskInput*, 2> keyframes = {&filteredKeyframe(inputs, before),
                                                     &filteredKeyframe(inputs, after)};
  // The keyframes are read a component at a time (a 1080p pair is gigabytes); first their
  // frame-wide channels, with each component's colors and emission for a moment: directly
  // seen light is not interpolated (the frame's own feature render has it exactly), so it
  // leaves the beauty here and each component's colors when the component is read.
  std::array<FrameImage, 2> frameWide;
  for (size_t k = 0; k < 2; ++k) {
    FrameImage read = keyframes[k]->part({[](const std::string& name) {
      return isFrameWideChannel(name) || name.find(".color.") != std::string::npos ||
             name.find(".emission.") != std::string::npos;
    }});
    for (const std::string& component : decompositionComponents(read))
      takeFromBeauty(read, directEmissionOf(read, component), component);
    read.removeChannels([](const std::string& name) { return !isFrameWideChannel(name); });
    frameWide[k] = std::move(read);
  }
  const std::vector<std::string> components = decompositionComponents(frameWide[0]);
  for (const TaskInput& input : inputs)
    if (input.kind == TASK_FLOW &&
        std::find(components.begin(), components.end(), input.params.component()) == components.end())
      throw BadInput("a flow of component \"" + input.params.component() + "\", which the keyframes do not have");
  const ComponentMotion frameWideMotion = keyframeMotion(frameWide[0], frameWide[1], "");
  std::mutex reading;  // a task's inputs are read by one thread at a time
  LayeredKeyframes keys;
  keys.frameWide = {&frameWide[0], &frameWide[1]};
  keys.frameWideMotion = &frameWideMotion;
  keys.component = [&](const std::string& component) {
    const auto ofComponent = [&](const std::string& name) {
      return name.rfind(component + ".", 0) == 0 || name == "depth.Z";
    };
    std::array<std::shared_ptr<FrameImage>, 2> parts;
    {
      const std::lock_guard lock(reading);
      for (size_t k = 0; k < 2; ++k) parts[k] = std::make_shared<FrameImage>(keyframes[k]->part({ofComponent}));
    }
    for (const auto& part : parts) takeComponentEmission(*part, component);
    auto motion = std::make_shared<ComponentMotion>(keyframeMotion(*parts[0], *parts[1], component));
    for (const TaskInput& input : inputs) {
      if (input.kind != TASK_FLOW || input.params.component() != component) continue;
      const std::lock_guard lock(reading);
      motion->irradianceForward = readMotionField(input.image(), component + ".irradiance_forward");
      motion->irradianceBackward = readMotionField(input.image(), component + ".irradiance_backward");
      motion->hasIrradianceMotion = true;
    }
    return KeyframeComponent{{parts[0], parts[1]}, motion};
  };
  const float fraction = static_cast<float>(params.frame() - before) / static_cast<float>(after - before);
  // Light seen by one keyframe only, with nothing nearby to tell whether it changed, is
  // left to the radiance check below: it compares the frame's own render there.
  InterpolationSettings settings;
  settings.unknownChangeMasks = false;
  InterpolationResult result = interpolateFrameDetailed(keys, fraction, settings);
  for (const auto& [key, value] : frameWide[0].attributes()) result.frame.attributes().emplace(key, value);
  result.frame.attributes()["pathfarm.frame"] = std::to_string(params.frame());
  result.frame.attributes()["pathfarm.interpolated"] =
      "between keyframes " + std::to_string(before) + " and " + std::to_string(after);
  // The keyframes are let go before the frame's feature render is decoded.
  frameWide = {};
  const FrameImage& features = inputOf(inputs, TASK_ASSEMBLE_FRAME, params.frame()).image();
  const FrameImage directLight = directEmissionOf(features);
  addDirectEmission(result.frame, directLight);
  // Where the frame's own features or their light disagree, the interpolation is wrong;
  // where its directly seen light has an edge, the feature render's few samples are; a
  // moving caustic no keyframe can carry: re-render there too.
  const std::vector<uint8_t> mismatch = featureMismatch(result.frame, features);
  const std::vector<uint8_t> edges = directLightEdges(directLight, features);
  const std::vector<uint8_t> lightMismatch = radianceMismatch(result.frame, features);
  const std::vector<uint8_t> caustics = movingCausticPixels(features);
  size_t mismatched = 0, edgePixels = 0, lightMismatched = 0, causticPixels = 0;
  std::vector<float>& flagged = result.frame.channel("rerender.Y");
  for (size_t p = 0; p < mismatch.size(); ++p) {
    mismatched += mismatch[p];
    edgePixels += edges[p];
    lightMismatched += lightMismatch[p];
    causticPixels += caustics[p];
    if (!mismatch[p] && !edges[p] && !lightMismatch[p] && !caustics[p]) continue;
    result.mask[p] = 1;
    flagged[p] = 1.0f;
  }
  TaskOutput output;
  requestRerender(lease.spec(), params.frame(), result.mask, output);
  // Why pixels were flagged (a pixel may have several causes).
  output.metrics["rerender_holes"] = static_cast<double>(result.holePixels);
  output.metrics["rerender_silhouettes"] = static_cast<double>(result.silhouettePixels);
  output.metrics["rerender_untracked"] = static_cast<double>(result.untrackedPixels);
  output.metrics["rerender_illumination"] = static_cast<double>(result.illuminationPixels);
  output.metrics["rerender_mismatch"] = static_cast<double>(mismatched);
  output.metrics["rerender_light_edges"] = static_cast<double>(edgePixels);
  output.metrics["rerender_light_mismatch"] = static_cast<double>(lightMismatched);
  output.metrics["rerender_moving_caustics"] = static_cast<double>(causticPixels);
  output.chunk = encodeExr(result.frame, ExrCompression::Fast);
  return output;
}

}  // namespace pathfarm::farm
