// Irradiance flow and frame interpolation between two keyframes (worker/filter_tasks.h).
#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>

#include "contract/pipeline.h"
#include "image/exr_io.h"
#include "postproc/filters/decomposed_frame.h"
#include "postproc/filters/direct_emission.h"
#include "postproc/interpolation/frame_interpolation.h"
#include "postproc/interpolation/in_between_checks.h"
#include "postproc/interpolation/interpolation_input.h"
#include "postproc/interpolation/irradiance_flow.h"
#include "worker/failure_class.h"
#include "worker/filter_inputs.h"

namespace pathfarm::farm {
namespace {

// A render's samples per pixel as its attribute `name` says (pathfarm.spp,
// pathfarm.reflectance_spp), or 0 where it does not say.
int sppAttribute(const FrameImage& frame, const std::string& name) {
  const auto found = frame.attributes().find(name);
  if (found == frame.attributes().end()) return 0;
  try {
    return std::stoi(found->second);
  } catch (const std::exception&) {
    return 0;
  }
}

// The samples per pixel of a render's reflectance: its own samples' where it took more.
int reflectanceSpp(const FrameImage& frame) {
  return std::max(sppAttribute(frame, "pathfarm.spp"), sppAttribute(frame, "pathfarm.reflectance_spp"));
}

// A component's motion between the keyframes (the frame-wide one for ""): forward from
// k0's motion vectors, backward from k1's, which reach each other (planner.h).
ComponentMotion keyframeMotion(const FrameImage& k0, const FrameImage& k1, const std::string& layer) {
  const std::string prefix = layer.empty() ? "" : layer + ".";
  return ComponentMotion(motionTowards(k0, NeighbourFrame::Next, prefix, "keyframe 0"),
                         motionTowards(k1, NeighbourFrame::Previous, prefix, "keyframe 1"));
}

// The causes an in-between frame's pixels are re-rendered for, as the report names them;
// bit c of the output's `rerender_causes.Y` is kRerenderCauses[c].
constexpr std::array<const char*, 8> kRerenderCauses = {"holes",    "silhouettes", "untracked",      "illumination",
                                                        "mismatch", "light_edges", "light_mismatch", "moving_caustics"};

// Rows `rows` of a frame `width` pixels wide held as an image or a byte per pixel, and
// some of those rows cut out of it (the image moved on when they are all of it).
struct Rows {
  RowWindow rows;
  int width;

  FrameImage crop(FrameImage image, const RowWindow& part) const {
    if (part.first == rows.first && part.end == rows.end) return image;
    return image.crop(0, part.first - rows.first, width, part.end - part.first);
  }
  std::vector<uint8_t> crop(const std::vector<uint8_t>& flags, const RowWindow& part) const {
    if (flags.size() != static_cast<size_t>(rows.end - rows.first) * static_cast<size_t>(width))
      throw std::logic_error("a mask is not of the rows it is cut from");
    const auto row = [&](int y) { return flags.begin() + static_cast<ptrdiff_t>(y - rows.first) * width; };
    return std::vector<uint8_t>(row(part.first), row(part.end));
  }
};

// Whether a channel is the vertical part of `buffer` ("motion", "irradiance_forward"),
// frame-wide or a component's.
bool isVerticalPartOf(const std::string& name, const std::string& buffer) {
  const std::string suffix = buffer + ".Y";
  return name == suffix || (name.size() > suffix.size() && name.ends_with("." + suffix));
}

// The largest magnitude of the finite values of the channels `keep` accepts, read a strip
// of rows at a time.
float largestOf(const TaskInput& input, const ChannelFilter& keep, int height) {
  constexpr int kStrip = 256;
  float largest = 0.0f;
  for (int y = 0; y < height; y += kStrip) {
    const FrameImage strip = input.part({keep, y, std::min(height, y + kStrip)});
    for (const std::string& name : strip.channelNames())
      for (const float value : strip.channel(name))
        if (std::isfinite(value)) largest = std::max(largest, std::abs(value));
  }
  return largest;
}

// How far, in rows, the interpolation at `fraction` reaches in the keyframes (every finite
// value of their motions and the flows', valid or not: bounds).
struct KeyframeReach {
  // The most rows content moves by: keyframe 0's motions towards keyframe 1 and the flows'
  // forward ones times the fraction, keyframe 1's and the backward ones times the rest.
  int landing = 0;
  // The most rows a whole motion spans: a pixel's depth at the in-between instant is read
  // where its motion leads in the other keyframe.
  int motion = 0;
};

KeyframeReach keyframeReach(const std::vector<TaskInput>& inputs, const std::array<const TaskInput*, 2>& keyframes,
                            float fraction, int height) {
  float forward = largestOf(*keyframes[0], [](const std::string& n) { return isVerticalPartOf(n, "motion"); }, height);
  float backward =
      largestOf(*keyframes[1], [](const std::string& n) { return isVerticalPartOf(n, "motion_back"); }, height);
  for (const TaskInput& input : inputs) {
    if (input.kind != TASK_FLOW) continue;
    forward = std::max(forward, largestOf(input, [](const std::string& n) {
                         return isVerticalPartOf(n, "irradiance_forward");
                       }, height));
    backward = std::max(backward, largestOf(input, [](const std::string& n) {
                          return isVerticalPartOf(n, "irradiance_backward");
                        }, height));
  }
  const auto rows = [height](float value) {
    return static_cast<int>(std::min(std::ceil(value), static_cast<float>(height)));
  };
  return {rows(std::max(fraction * forward, (1.0f - fraction) * backward)), rows(std::max(forward, backward))};
}

// The rows of a flow whose band held none of the component: summed over windows by the join.
const char* const kFlowSkippedRows = "pathfarm.flow_skipped_rows";

// The channels of a keyframe's component a flow band reads: its irradiance and its motion
// `towards` the other keyframe alone (a 4K keyframe's other channels are gigabytes).
ChannelFilter flowChannelsOf(const std::string& component, NeighbourFrame towards) {
  const std::string motion = towards == NeighbourFrame::Next ? "motion" : "motion_back";
  return [component, motion](const std::string& name) {
    if (name.rfind(component + ".", 0) != 0) return false;
    const std::string buffer = name.substr(component.size() + 1, name.rfind('.') - component.size() - 1);
    return buffer == "irradiance" || buffer == motion || buffer == "motion_valid";
  };
}

// A keyframe of the shot's size, else BadInput: a band reads rows of it by the shot's.
void checkKeyframeSize(const TaskInput& keyframe, int width, int height, const std::string& label) {
  const FrameImage header = keyframe.part({[](const std::string&) { return false; }});
  if (header.width() != width || header.height() != height)
    throw BadInput(label + " is " + std::to_string(header.width()) + "x" + std::to_string(header.height()) +
                   ", the shot " + std::to_string(width) + "x" + std::to_string(height));
}

// A keyframe's component as a flow band reads it (irradiance_flow.h), decoded a band's
// rows at a time: its irradiance and its motion `towards` the other keyframe, or its
// irradiance alone.
ComponentRows flowRowsOf(const TaskInput& keyframe, const std::string& component, NeighbourFrame towards, int width,
                         int height, const std::string& label) {
  const std::string prefix = component + ".irradiance.";
  const auto irradianceOf = [prefix, width, label](const FrameImage& part) {
    Planes planes(width, part.height(), 0);
    for (const char* rgb : {"R", "G", "B"}) planes.channels.push_back(finiteChannel(part, prefix + rgb, label));
    return planes;
  };
  ComponentRows rows{width, height, {}, {}};
  rows.irradiance = [&keyframe, prefix, irradianceOf](int first, int end) {
    return irradianceOf(keyframe.part({[&](const std::string& name) { return name.rfind(prefix, 0) == 0; }, first, end}));
  };
  rows.rows = [&keyframe, component, towards, height, label, irradianceOf](int first, int end) {
    const FrameImage part = keyframe.part({flowChannelsOf(component, towards), first, end});
    MotionField motion = motionTowards(part, towards, component + ".", label);
    motion.top = first;
    motion.frameHeight = height;
    return ComponentBand{irradianceOf(part), std::move(motion)};
  };
  return rows;
}

}  // namespace

TaskOutput runFlowTask(const Lease& lease, std::vector<TaskInput>& inputs) {
  const TaskParams& params = lease.params();
  const std::string& component = params.component();
  if (joinsWindows(lease, inputs)) {
    for (const TaskInput& input : inputs)
      if (input.params.component() != component)
        throw BadInput("the join of component " + component + "'s flow takes a window of component " +
                       input.params.component());
    TaskOutput output;
    const JoinedWindows windows = joinRowWindows(lease, inputs, "flows", {}, output, {.flagged = false});
    addJoinedAttributes(output, summedCounts(windows, {kFlowSkippedRows}, "the flow of component " + component));
    return output;
  }
  const int width = lease.spec().width(), height = lease.spec().height();
  const RowWindow wanted = rowsOf(lease, "the flow");
  TaskInput& k0 = filteredKeyframe(inputs, params.keyframe_before());
  TaskInput& k1 = filteredKeyframe(inputs, params.keyframe_after());
  checkKeyframeSize(k0, width, height, "keyframe 0");
  checkKeyframeSize(k1, width, height, "keyframe 1");
  const std::vector<std::string> components =
      decompositionComponents(k0.part({flowChannelsOf(component, NeighbourFrame::Next), 0, 1}));
  if (component.empty() || std::find(components.begin(), components.end(), component) == components.end())
    throw BadInput("the keyframes have no component " + component);
  // Each band of the flow reads the rows it is solved on alone (irradiance_flow.h).
  const IrradianceFlows flows = irradianceFlowRows(
      flowRowsOf(k0, component, NeighbourFrame::Next, width, height, "keyframe 0"),
      flowRowsOf(k1, component, NeighbourFrame::Previous, width, height, "keyframe 1"), wanted.first, wanted.end,
      FlowSettings{});
  FrameImage chunk(width, wanted.end - wanted.first);
  chunk.attributes()["pathfarm.flow"] =
      "irradiance flow, log domain, bootstrapped by the primary motion, in bands of at most " +
      std::to_string(FlowBanding{}.rows) + " rows";
  // Bands where both keyframes lack the component have nothing to track: their flow is
  // invalid and interpolation falls back to the primary motion there.
  chunk.attributes()[kFlowSkippedRows] = std::to_string(flows.skippedRows);
  writeMotionField(chunk, component + ".irradiance_forward", flows.forward);
  writeMotionField(chunk, component + ".irradiance_backward", flows.backward);
  TaskOutput output;
  output.chunk = encodeExr(chunk, ExrCompression::Fast);
  return output;
}

TaskOutput runInterpolateTask(const Lease& lease, std::vector<TaskInput>& inputs) {
  if (joinsWindows(lease, inputs)) return joinedWithRerender(lease, inputs, "interpolations");
  const TaskParams& params = lease.params();
  const int width = lease.spec().width(), height = lease.spec().height();
  const int64_t before = params.keyframe_before(), after = params.keyframe_after();
  const std::array<const TaskInput*, 2> keyframes = {&filteredKeyframe(inputs, before),
                                                     &filteredKeyframe(inputs, after)};
  // Light seen by one keyframe only, with nothing nearby to tell whether it changed, is
  // left to the radiance check below: it compares the frame's own render there.
  InterpolationSettings settings;
  settings.unknownChangeMasks = false;
  const float fraction = static_cast<float>(params.frame() - before) / static_cast<float>(after - before);
  // The rows computed (a window's, or all), the rows the checks read around them, and the
  // rows of the keyframes whose content can move into those (all of them without a window).
  const RowWindow wanted = rowsOf(lease, "the interpolation");
  const int reach = std::max(inBetweenChecksReach(), settings.illuminationRadius);
  const RowWindow checked{std::max(0, wanted.first - reach), std::min(height, wanted.end + reach)};
  RowWindow read{0, height};
  int displacement = 0;
  if (params.has_window()) {
    // A source lands on its row plus its displacement's whole rows, and the row below; its
    // depth is read where its whole motion leads, rounded to a pixel.
    const KeyframeReach reach = keyframeReach(inputs, keyframes, fraction, height);
    displacement = reach.landing;
    const int margin = reach.landing + reach.motion + 2;
    read = {std::max(0, checked.first - margin), std::min(height, checked.end + margin)};
  }

  // The keyframes are read a component at a time (a 1080p pair is gigabytes); first their
  // frame-wide channels, with each component's colors and emission for a moment: directly
  // seen light is not interpolated (the frame's own feature render has it exactly), so it
  // leaves the beauty here and each component's colors when the component is read.
  std::array<FrameImage, 2> frameWide;
  for (size_t k = 0; k < 2; ++k) {
    FrameImage part = keyframes[k]->part({[](const std::string& name) {
                                            return isFrameWideChannel(name) || name.find(".color.") != std::string::npos ||
                                                   name.find(".emission.") != std::string::npos;
                                          },
                                          read.first, read.end});
    for (const std::string& component : decompositionComponents(part))
      takeFromBeauty(part, directEmissionOf(part, component), component);
    part.removeChannels([](const std::string& name) { return !isFrameWideChannel(name); });
    frameWide[k] = std::move(part);
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
      for (size_t k = 0; k < 2; ++k)
        parts[k] = std::make_shared<FrameImage>(keyframes[k]->part({ofComponent, read.first, read.end}));
    }
    for (const auto& part : parts) takeComponentEmission(*part, component);
    auto motion = std::make_shared<ComponentMotion>(keyframeMotion(*parts[0], *parts[1], component));
    for (const TaskInput& input : inputs) {
      if (input.kind != TASK_FLOW || input.params.component() != component) continue;
      const std::lock_guard lock(reading);
      const FrameImage flow = input.part({{}, read.first, read.end});
      motion->irradianceForward = readMotionField(flow, component + ".irradiance_forward");
      motion->irradianceBackward = readMotionField(flow, component + ".irradiance_backward");
      motion->hasIrradianceMotion = true;
    }
    return KeyframeComponent{{parts[0], parts[1]}, motion};
  };
  // The frame's own reflectance modulates its interpolated irradiance at texture edges, which
  // the keyframes' splat blurs and misplaces, when its feature render's reflectance has the
  // samples the planner gives it (ownReflectanceSpp): with fewer, its noise costs more than
  // the edges gain (docs/performance.md, "The in-between frame's own reflectance").
  const TaskInput& featureInput = inputOf(inputs, TASK_ASSEMBLE_FRAME, params.frame());
  const FrameImage ownReflectance = featureInput.part(
      {[](const std::string& name) { return name.find(".reflectance.") != std::string::npos; }, read.first, read.end});
  if (reflectanceSpp(ownReflectance) >= ownReflectanceSpp(sppAttribute(frameWide[0], "pathfarm.spp")))
    keys.inBetween = &ownReflectance;
  InterpolationResult result = interpolateFrameDetailed(keys, fraction, settings);
  for (const auto& [key, value] : frameWide[0].attributes()) result.frame.attributes().emplace(key, value);
  result.frame.attributes()["pathfarm.frame"] = std::to_string(params.frame());
  result.frame.attributes()["pathfarm.interpolated"] =
      "between keyframes " + std::to_string(before) + " and " + std::to_string(after);
  // The interpolation's own rate leaves out the checks below; the frame's re-render is
  // counted by its composite.
  result.frame.attributes().erase("pathfarm.rerender_rate");
  // The keyframes are let go before the frame's feature render is read.
  frameWide = {};
  const Rows inRead{read, width};
  FrameImage interpolated = inRead.crop(std::move(result.frame), checked);
  // The feature render's rows the checks read: the decoded frame itself when they are all of it.
  std::optional<FrameImage> featureRows;
  if (checked.first != 0 || checked.end != height) featureRows = featureInput.part({{}, checked.first, checked.end});
  const FrameImage& features = featureRows ? *featureRows : featureInput.image();
  const FrameImage directLight = directEmissionOf(features);
  addDirectEmission(interpolated, directLight);
  // Where the frame's own features or their light disagree, the interpolation is wrong;
  // where its directly seen light has an edge, the feature render's few samples are; a
  // moving caustic no keyframe can carry: re-render there too.
  const Rows inChecked{checked, width};
  const InBetweenChecks checks = checkInBetween(interpolated, features, directLight);
  const std::vector<uint8_t> mismatch = inChecked.crop(checks.mismatch, wanted);
  const std::vector<uint8_t> edges = inChecked.crop(checks.lightEdges, wanted);
  const std::vector<uint8_t> lightMismatch = inChecked.crop(checks.lightMismatch, wanted);
  const std::vector<uint8_t> caustics = inChecked.crop(checks.caustics, wanted);
  interpolated = inChecked.crop(std::move(interpolated), wanted);
  std::vector<uint8_t> mask = inRead.crop(result.mask, wanted);
  std::vector<float>& flagged = interpolated.channel("rerender.Y");
  for (size_t p = 0; p < mask.size(); ++p) {
    if (!mismatch[p] && !edges[p] && !lightMismatch[p] && !caustics[p]) continue;
    mask[p] = 1;
    flagged[p] = 1.0f;
  }
  // Why each pixel was flagged, a bit per cause in the order of kRerenderCauses (`pathfarm
  // compare --mask OUTPUT.exr:rerender_causes.Y=16` measures the pixels the feature
  // mismatch alone flagged).
  const std::array<std::vector<uint8_t>, kRerenderCauses.size()> causes = {
      inRead.crop(result.holes, wanted), inRead.crop(result.silhouettes, wanted),
      inRead.crop(result.untracked, wanted), inRead.crop(result.illumination, wanted), mismatch, edges, lightMismatch,
      caustics};
  std::vector<float>& causeBits = interpolated.addChannel("rerender_causes.Y");
  for (size_t p = 0; p < mask.size(); ++p)
    for (size_t c = 0; c < causes.size(); ++c) causeBits[p] += causes[c][p] ? static_cast<float>(1u << c) : 0.0f;
  TaskOutput output;
  // A window's flags go to the re-render with the frame's, from the join.
  if (!params.has_window()) requestRerender(lease.spec(), params.frame(), mask, output);
  // Why pixels were flagged (a pixel may have several causes).
  const auto count = [](const std::vector<uint8_t>& flags) {
    return static_cast<double>(std::count(flags.begin(), flags.end(), 1));
  };
  for (size_t c = 0; c < causes.size(); ++c)
    output.metrics["rerender_" + std::string(kRerenderCauses[c])] = count(causes[c]);
  // How much of the keyframes a window read, and why: all of them when the motion is large.
  if (params.has_window()) {
    output.metrics["keyframe_rows_read"] = static_cast<double>(read.end - read.first);
    output.metrics["displacement_rows"] = static_cast<double>(displacement);
  }
  output.frame = std::move(interpolated);
  return output;
}

}  // namespace pathfarm::farm
