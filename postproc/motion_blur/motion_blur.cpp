#include "postproc/motion_blur/motion_blur.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>
#include <limits>
#include <queue>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "postproc/filters/decomposed_frame.h"
#include "postproc/interpolation/forward_splat.h"

namespace pathfarm {
namespace {

const std::vector<float>& finiteChannel(const FrameImage& frame, const std::string& name) {
  if (!frame.hasChannel(name)) throw std::invalid_argument("motion blur: missing channel \"" + name + "\"");
  const std::vector<float>& plane = frame.channel(name);
  for (float v : plane)
    if (!std::isfinite(v)) throw std::invalid_argument("motion blur: channel \"" + name + "\" has a non-finite value");
  return plane;
}

struct BlurLayer {
  std::string color[3];
  std::string prefix;  // of the motion and depth channels
  std::string depth;
};

// Fills the pixels with known == 0 from known 4-neighbours, the deepest known surface
// first: a region a moving surface uncovered takes the farthest surface bordering it,
// propagated across the region, never the nearer moving surface on its other side.
// Pixels with no known pixel anywhere stay unknown.
void fillDeepestFirst(Planes& values, std::vector<float>& depth, std::vector<uint8_t>& known) {
  const int width = values.width, height = values.height;
  struct Candidate {
    float depth;
    size_t target, from;
    bool operator<(const Candidate& o) const { return depth < o.depth || (depth == o.depth && target > o.target); }
  };
  std::priority_queue<Candidate> queue;
  auto pushNeighbours = [&](size_t p) {
    const int x = static_cast<int>(p % static_cast<size_t>(width)), y = static_cast<int>(p / static_cast<size_t>(width));
    const int nx[4] = {x - 1, x + 1, x, x}, ny[4] = {y, y, y - 1, y + 1};
    const float d = std::isnan(depth[p]) ? 0.0f : depth[p];
    for (int k = 0; k < 4; ++k) {
      if (nx[k] < 0 || nx[k] >= width || ny[k] < 0 || ny[k] >= height) continue;
      const size_t n = static_cast<size_t>(ny[k]) * static_cast<size_t>(width) + static_cast<size_t>(nx[k]);
      if (!known[n]) queue.push(Candidate{d, n, p});
    }
  };
  for (size_t p = 0; p < known.size(); ++p)
    if (known[p]) pushNeighbours(p);
  while (!queue.empty()) {
    const Candidate c = queue.top();
    queue.pop();
    if (known[c.target]) continue;
    known[c.target] = 1;
    depth[c.target] = depth[c.from];
    for (auto& plane : values.channels) plane[c.target] = plane[c.from];
    pushNeighbours(c.target);
  }
}

// Fills the motion of pixels where `valid` is 0 by inpainting: each takes the motion of its
// nearest valid pixel (breadth-first over 4-neighbours, so the result is deterministic).
// Where the component has no valid pixel at all, the frame-wide primary motion (`fallback`,
// may be null) stands in, or no motion. Only planes that are not empty are filled.
void inpaintMotion(std::vector<float>* planes[4], const std::vector<float>& valid, int width, int height,
                   const std::vector<float>* const fallback[4]) {
  const size_t pixels = valid.size();
  std::vector<size_t> source(pixels, SIZE_MAX);
  std::queue<size_t> frontier;
  for (size_t p = 0; p < pixels; ++p)
    if (valid[p] >= 0.5f) {
      source[p] = p;
      frontier.push(p);
    }
  while (!frontier.empty()) {
    const size_t p = frontier.front();
    frontier.pop();
    const int x = static_cast<int>(p % static_cast<size_t>(width)), y = static_cast<int>(p / static_cast<size_t>(width));
    const std::pair<int, int> neighbours[4] = {{x - 1, y}, {x + 1, y}, {x, y - 1}, {x, y + 1}};
    for (const auto& [nx, ny] : neighbours) {
      if (nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
      const size_t q = static_cast<size_t>(ny) * static_cast<size_t>(width) + static_cast<size_t>(nx);
      if (source[q] != SIZE_MAX) continue;
      source[q] = source[p];
      frontier.push(q);
    }
  }
  for (size_t p = 0; p < pixels; ++p) {
    if (valid[p] >= 0.5f) continue;
    for (int i = 0; i < 4; ++i) {
      if (planes[i]->empty()) continue;
      (*planes[i])[p] = source[p] != SIZE_MAX ? (*planes[i])[source[p]] : (fallback[i] ? (*fallback[i])[p] : 0.0f);
    }
  }
}

// The layers blurred on their own: every component, or the beauty without a decomposition.
std::vector<BlurLayer> blurLayersOf(const std::vector<std::string>& components) {
  std::vector<BlurLayer> layers;
  if (components.empty()) layers.push_back(BlurLayer{{"R", "G", "B"}, "", "depth.Z"});
  for (const std::string& c : components)
    layers.push_back(BlurLayer{{c + ".color.R", c + ".color.G", c + ".color.B"}, c + ".", c + ".depth.Z"});
  return layers;
}

// A layer as the blur reads it.
struct BlurInput {
  Planes values;
  const std::vector<float>* depth = nullptr;
  std::vector<float> fx, fy, bx, by;  // forward and backward motion, 0 where invalid
};

// Reads and checks the layer's channels; the backward motion only for a centered shutter.
BlurInput readBlurInput(const FrameImage& frame, const BlurLayer& layer, bool centered) {
  const int width = frame.width(), height = frame.height();
  BlurInput in;
  in.values = Planes(width, height, 3);
  for (size_t c = 0; c < 3; ++c) in.values.channels[c] = finiteChannel(frame, layer.color[c]);
  in.depth = &finiteChannel(frame, layer.depth);
  const std::string& pre = layer.prefix;
  in.fx = finiteChannel(frame, pre + "motion.X");
  in.fy = finiteChannel(frame, pre + "motion.Y");
  if (centered) {
    in.bx = finiteChannel(frame, pre + "motion_back.X");
    in.by = finiteChannel(frame, pre + "motion_back.Y");
  }
  if (frame.hasChannel(pre + "motion_valid.Y")) {
    // Undefined (specular) motion is inpainted from the component's own valid motion,
    // or from the frame-wide primary motion where the component has none.
    std::vector<float>* planes[4] = {&in.fx, &in.fy, &in.bx, &in.by};
    const char* names[4] = {"motion.X", "motion.Y", "motion_back.X", "motion_back.Y"};
    const std::vector<float>* fallback[4] = {};
    for (int k = 0; k < 4; ++k)
      if (!pre.empty() && frame.hasChannel(names[k])) fallback[k] = &finiteChannel(frame, names[k]);
    inpaintMotion(planes, finiteChannel(frame, pre + "motion_valid.Y"), width, height, fallback);
  }
  return in;
}

// The background of every partly covered pixel of splat `r`: its own unmoved value where
// that surface stays in place and was hidden by the depth test, else the fully covered
// pixels, with the rest filled deepest surface first (what a moving surface uncovers).
// `known` is 0 where no background was found.
void findBackground(const BlurInput& in, const SplatSource& source, const SplatResult& r, float depthTolerance,
                    Planes& background, std::vector<float>& backgroundDepth, std::vector<uint8_t>& known) {
  for (size_t p = 0; p < known.size(); ++p) {
    known[p] = 0;
    const float own = (*in.depth)[p] > 0.0f ? (*in.depth)[p] : std::numeric_limits<float>::infinity();
    if (source.dx[p] == 0.0f && source.dy[p] == 0.0f && r.covered[p] &&
        !(own <= r.depth[p] * (1.0f + depthTolerance) + 1e-6f)) {
      known[p] = 1;
      backgroundDepth[p] = own;
      for (size_t c = 0; c < 3; ++c) background.channels[c][p] = in.values.channels[c][p];
    } else if (r.covered[p] && r.weight[p] >= 0.999f) {
      known[p] = 1;
      backgroundDepth[p] = r.depth[p];
      for (size_t c = 0; c < 3; ++c) background.channels[c][p] = r.values.channels[c][p];
    }
  }
  fillDeepestFirst(background, backgroundDepth, known);
}

// One layer splatted at each of the exposure's times and averaged.
Planes blurLayer(const BlurInput& in, float exposure, const MotionBlurSettings& settings) {
  const int width = in.values.width, height = in.values.height;
  const size_t pixels = in.values.pixelCount();
  const bool centered = settings.shutter == Shutter::Centered;
  const int steps = settings.steps;
  // Every contribution counts (strongFootprint 0): the nearest surface at a pixel keeps its
  // footprint weight w and the rest, 1 - w, is composited from the background below, so
  // a splat of weight w is never renormalized to 1 (which gains energy) nor averaged with
  // the background it partly covers (which loses it). minCoverage only guards the division.
  const SplatSettings splat{settings.depthTolerance, 1e-6f, 0.0f};
  std::vector<double> sum(3 * pixels, 0.0);
  SplatSource source;
  source.values = &in.values;
  source.depth = in.depth;
  source.dx.resize(pixels);
  source.dy.resize(pixels);
  Planes background(width, height, 3);
  std::vector<float> backgroundDepth(pixels);
  std::vector<uint8_t> known(pixels);
  for (int k = 0; k < steps; ++k) {
    const float u = (static_cast<float>(k) + 0.5f) / static_cast<float>(steps);
    const float tau = centered ? exposure * (u - 0.5f) : exposure * u;
    const bool back = tau < 0.0f;
    const float scale = std::fabs(tau);
    for (size_t p = 0; p < pixels; ++p) {
      source.dx[p] = scale * (back ? in.bx[p] : in.fx[p]);
      source.dy[p] = scale * (back ? in.by[p] : in.fy[p]);
    }
    const SplatResult r = forwardSplat(source, splat);
    findBackground(in, source, r, settings.depthTolerance, background, backgroundDepth, known);
    for (size_t c = 0; c < 3; ++c)
      for (size_t p = 0; p < pixels; ++p) {
        const float bg = known[p] ? background.channels[c][p] : in.values.channels[c][p];
        const float w = r.covered[p] ? r.weight[p] : 0.0f;
        // w >= 1: the normalized splat; w < 1: the kept contributions (w * normalized
        // value = their weighted sum) plus (1 - w) of the background.
        sum[c * pixels + p] += w >= 1.0f ? r.values.channels[c][p] : w * r.values.channels[c][p] + (1.0f - w) * bg;
      }
  }
  Planes blurred(width, height, 3);
  for (size_t c = 0; c < 3; ++c)
    for (size_t p = 0; p < pixels; ++p)
      blurred.channels[c][p] = static_cast<float>(sum[c * pixels + p] / static_cast<double>(steps));
  return blurred;
}

// `frame` with the blurred layers' colors and their sum as the beauty R, G, B.
FrameImage withBlurredLayers(const FrameImage& frame, const std::vector<BlurLayer>& layers,
                             const std::vector<Planes>& blurred, bool decomposed) {
  const size_t pixels = frame.pixelCount();
  FrameImage out = frame;
  const char* rgb[3] = {"R", "G", "B"};
  for (size_t c = 0; c < 3; ++c) {
    std::vector<float>& beauty = out.addChannel(rgb[c]);
    if (!decomposed) {
      beauty = blurred[0].channels[c];
      continue;
    }
    beauty.assign(pixels, 0.0f);
    for (size_t i = 0; i < layers.size(); ++i) {
      out.channel(layers[i].color[c]) = blurred[i].channels[c];
      for (size_t p = 0; p < pixels; ++p) beauty[p] += blurred[i].channels[c][p];
    }
  }
  return out;
}

}  // namespace

FrameImage motionBlur(const FrameImage& frame, float exposure, const MotionBlurSettings& settings) {
  if (!std::isfinite(exposure) || exposure < 0.0f)
    throw std::invalid_argument("motion blur: the exposure must be finite and >= 0, got " + std::to_string(exposure));
  if (settings.steps < 1) throw std::invalid_argument("motion blur: steps must be >= 1");
  if (frame.width() <= 0 || frame.height() <= 0) throw std::invalid_argument("motion blur: the frame is empty");

  const std::vector<std::string> components = decompositionComponents(frame);
  const std::vector<BlurLayer> layers = blurLayersOf(components);
  // Read and check everything before any work.
  std::vector<BlurInput> inputs(layers.size());
  for (size_t i = 0; i < layers.size(); ++i)
    inputs[i] = readBlurInput(frame, layers[i], settings.shutter == Shutter::Centered);

  std::vector<Planes> blurred(layers.size());
  tbb::parallel_for(size_t(0), layers.size(), [&](size_t i) { blurred[i] = blurLayer(inputs[i], exposure, settings); });

  FrameImage out = withBlurredLayers(frame, layers, blurred, !components.empty());
  out.attributes()["pathfarm.motion_blur"] = std::to_string(exposure);
  return out;
}

}  // namespace pathfarm
