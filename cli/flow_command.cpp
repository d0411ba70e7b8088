// `pathfarm flow A.exr B.exr --layer LAYER --out FLOW.exr`: optical flow of one layer
// between two frames, bootstrapped by the renderer's primary motion, with occlusions.
#include <spdlog/spdlog.h>

#include <memory>

#include "cli/command.h"
#include "image/exr_io.h"
#include "postproc/flow/optical_flow.h"

namespace pathfarm {
namespace {

struct FlowArguments {
  std::string a, b, layer = "diffuse_direct.irradiance", out;
  FlowSettings settings;
  float occlusionThreshold = 0.1f;
};

Planes layerPlanes(const FrameImage& frame, const std::string& layer, const std::string& label) {
  Planes planes(frame.width(), frame.height(), 0);
  for (const char* c : {"R", "G", "B"}) {
    const std::string name = layer + "." + c;
    if (!frame.hasChannel(name)) throw std::invalid_argument(label + ": missing channel \"" + name + "\"");
    planes.channels.push_back(frame.channel(name));
  }
  return planes;
}

// The renderer's motion for the layer's component ("<component>.motion"), or the frame's.
FlowField primaryMotion(const FrameImage& frame, const std::string& layer, const char* buffer,
                        const std::string& label) {
  const std::string component = layer.substr(0, layer.find('.'));
  std::string prefix = component + "." + buffer;
  if (!frame.hasChannel(prefix + ".X")) prefix = buffer;
  if (!frame.hasChannel(prefix + ".X") || !frame.hasChannel(prefix + ".Y"))
    throw std::invalid_argument(label + ": missing channel \"" + prefix + ".X\" (a decomposed render's motion)");
  FlowField flow(frame.width(), frame.height());
  flow.dx = frame.channel(prefix + ".X");
  flow.dy = frame.channel(prefix + ".Y");
  return flow;
}

int runFlow(FlowArguments& a) {
  return runReportingBadInput([&] {
    const FrameImage first = readExr(a.a), second = readExr(a.b);
    // Irradiance is matched in the log domain: illumination changes are multiplicative.
    a.settings.logDomain = a.layer.size() >= 11 && a.layer.compare(a.layer.size() - 11, 11, ".irradiance") == 0;
    const Planes from = layerPlanes(first, a.layer, a.a), to = layerPlanes(second, a.layer, a.b);
    const FlowField forwardGuess = primaryMotion(first, a.layer, "motion", a.a);
    const FlowField backwardGuess = primaryMotion(second, a.layer, "motion_back", a.b);
    // Occluded pixels get their flow from the smoothness term alone.
    const OcclusionResult occlusion =
        forwardBackward(bootstrappedFlow(from, to, forwardGuess, a.settings),
                        bootstrappedFlow(to, from, backwardGuess, a.settings), a.occlusionThreshold);
    const FlowField flow = bootstrappedFlow(from, to, forwardGuess, a.settings, &occlusion.mask);
    FrameImage out(first.width(), first.height());
    out.addChannel("flow.X") = flow.dx;
    out.addChannel("flow.Y") = flow.dy;
    out.addChannel("occlusion.Y") = occlusion.mask;
    out.attributes()["pathfarm.flow"] = a.layer + (a.settings.logDomain ? " (log domain)" : "");
    writeExr(a.out, out);
    spdlog::info("{} -> {}: flow of {} written to {}; {} occluded pixels", a.a, a.b, a.layer, a.out, occlusion.count);
    return kExitOk;
  });
}

}  // namespace

std::vector<Command> addFlowCommand(CLI::App& app) {
  auto arguments = std::make_shared<FlowArguments>();
  CLI::App* flow = app.add_subcommand("flow", "optical flow of a layer between two frames (Brox et al. 2004)");
  flow->add_option("a", arguments->a, "the first frame (EXR)")->required();
  flow->add_option("b", arguments->b, "the second frame (EXR)")->required();
  flow->add_option("--layer", arguments->layer, "layer to match, e.g. diffuse_direct.irradiance")->capture_default_str();
  flow->add_option("--out", arguments->out, "output EXR: flow.X/Y and occlusion.Y")->required();
  flow->add_option("--lambda", arguments->settings.lambda, "smoothness weight (0.25 for caustics)")->capture_default_str();
  flow->add_option("--occlusion-threshold", arguments->occlusionThreshold, "forward-backward tolerance in pixels")
      ->capture_default_str();
  return {{flow, [arguments] { return runFlow(*arguments); }}};
}

}  // namespace pathfarm
