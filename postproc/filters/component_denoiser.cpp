#include "postproc/filters/component_denoiser.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "postproc/filters/firefly_spread.h"
#include "postproc/filters/warp.h"
#include "renderer/decomposition/effective_irradiance.h"

namespace pathfarm {
namespace {

const char* const kXyz[] = {"X", "Y", "Z"};

// One filtered layer: the beauty, or a component.
struct LayerSpec {
  std::string component;         // "" for the beauty
  std::string featureComponent;  // whose features guide it ("" for none)
  std::string motionPrefix;      // "" (frame-wide motion) or "<component>."
};

// A buffer of a layer's frame: a channel prefix and its channel suffixes.
struct Buffer {
  std::string prefix;
  std::vector<std::string> channels;
  FeatureKind kind = FeatureKind::Continuous;

  std::string name(size_t i) const { return prefix.empty() ? channels[i] : prefix + "." + channels[i]; }
};

Buffer rgb(const std::string& prefix) { return {prefix, {kRgbChannels[0], kRgbChannels[1], kRgbChannels[2]}}; }

std::vector<Buffer> featureBuffers(const LayerSpec& layer, const DenoiseSettings& s) {
  if (layer.featureComponent.empty()) return {};
  const std::string& c = layer.featureComponent;
  std::vector<Buffer> buffers = {{c + ".normal", {kXyz[0], kXyz[1], kXyz[2]}},
                                 rgb(c + ".reflectance"),
                                 {c + ".objectid", {"Y"}, FeatureKind::ExactMatch}};
  if (s.useDepth) buffers.push_back({c + ".depth", {"Z"}});
  return buffers;
}

// The buffers a frame must have for a layer, in load order: color, variance, (reflectance).
std::vector<Buffer> colorBuffers(const LayerSpec& layer) {
  if (layer.component.empty()) return {rgb(""), rgb("variance")};
  return {rgb(layer.component + ".irradiance"), rgb(layer.component + ".variance"),
          rgb(layer.component + ".reflectance")};
}

void requireBuffers(const FrameImage& frame, const std::vector<Buffer>& buffers, const std::string& label) {
  for (const Buffer& buffer : buffers)
    for (size_t i = 0; i < buffer.channels.size(); ++i) requireChannel(frame, buffer.name(i), label);
}

// A component's coverage to divide out (filterCoverage), or null for the beauty.
const std::vector<float>* coverageOf(const FrameImage& frame, const LayerSpec& layer) {
  return layer.component.empty() ? nullptr : filterCoverage(frame, layer.component);
}

Planes planesOf(const FrameImage& frame, const Buffer& buffer) {
  Planes planes;
  planes.width = frame.width();
  planes.height = frame.height();
  for (size_t i = 0; i < buffer.channels.size(); ++i) planes.channels.push_back(frame.channel(buffer.name(i)));
  return planes;
}

// A layer's buffers in one frame, before warping.
struct LayerFrame {
  Planes color, variance;
  std::vector<Planes> features;
};

LayerFrame loadLayer(const FrameImage& frame, const LayerSpec& layer, const std::vector<Buffer>& features) {
  const std::vector<Buffer> buffers = colorBuffers(layer);
  LayerFrame out;
  out.color = planesOf(frame, buffers[0]);
  out.variance = planesOf(frame, buffers[1]);
  if (!layer.component.empty()) {
    // The variance of the mean carried through the division by the reflectance.
    const Planes reflectance = planesOf(frame, buffers[2]);
    for (size_t c = 0; c < 3; ++c) {
      std::vector<float>& variance = out.variance.channels[c];
      const std::vector<float>& r = reflectance.channels[c];
      for (size_t p = 0; p < variance.size(); ++p)
        if (r[p] >= kReflectanceGuard) variance[p] /= r[p] * r[p];
    }
    // The light per covered area, so that a silhouette pixel reads as its neighbours do
    // (denoiseFrame multiplies its own coverage back).
    if (const std::vector<float>* coverage = coverageOf(frame, layer)) {
      for (size_t c = 0; c < 3; ++c) {
        std::vector<float>& color = out.color.channels[c];
        std::vector<float>& variance = out.variance.channels[c];
        for (size_t p = 0; p < color.size(); ++p) {
          color[p] = perCoveredArea(color[p], (*coverage)[p]);
          variance[p] = perCoveredArea(perCoveredArea(variance[p], (*coverage)[p]), (*coverage)[p]);
        }
      }
    }
  }
  for (const Buffer& buffer : features) out.features.push_back(planesOf(frame, buffer));
  return out;
}

bool allZero(const Planes& planes) {
  for (const auto& plane : planes.channels)
    if (std::any_of(plane.begin(), plane.end(), [](float v) { return v != 0.0f; })) return false;
  return true;
}

struct Neighbour {
  const FrameImage* frame;
  NeighbourFrame which;
  const std::string* label;
  int top = 0;  // the frame row of its row 0
};

// The current frame's motion towards a neighbour, placed in its frame for a window.
MotionField motionOf(const FrameImage& current, NeighbourFrame which, const LayerSpec& layer, const DenoiseSettings& s) {
  MotionField motion = motionTowards(current, which, layer.motionPrefix, s.label);
  if (s.window) {
    motion.top = s.window->currentTop;
    motion.frameHeight = s.window->frameHeight;
  }
  return motion;
}

// Whether a neighbour takes part in a layer's filter: some pixel warps validly onto it.
bool takesPart(const Neighbour& n, const LayerSpec& layer, const std::vector<float>& valid, const DenoiseSettings& s) {
  if (!s.window) return std::any_of(valid.begin(), valid.end(), [](float v) { return v != 0.0f; });
  const std::set<std::string>& reached =
      n.which == NeighbourFrame::Previous ? s.window->previousReached : s.window->nextReached;
  return reached.count(layer.component) > 0;
}

struct LayerResult {
  Planes color;  // filtered (irradiance for a component)
  std::vector<uint8_t> invalid;
  std::vector<size_t> fireflies;  // of the current frame, spread instead of filtered
};

// The guides of a firefly's spread among a layer's features (featureBuffers' order).
FireflySurface surfaceOf(const NlMeansFrame& frame) {
  FireflySurface surface;
  if (frame.features.size() >= 3) {
    surface.normal = &frame.features[0];
    surface.objectId = &frame.features[2];
  }
  return surface;
}

LayerResult filterLayer(const FrameImage& current, const std::vector<Neighbour>& neighbours, const LayerSpec& layer,
                        const DenoiseSettings& s) {
  const std::vector<Buffer> features = featureBuffers(layer, s);
  LayerResult result;
  NlMeansInput input;
  for (const Buffer& buffer : features) input.featureKinds.push_back(buffer.kind);

  LayerFrame first = loadLayer(current, layer, features);
  bool zero = allZero(first.color) && allZero(first.variance);
  std::vector<LayerFrame> loaded;
  std::vector<MotionField> motions;
  std::vector<std::vector<float>> valids;
  std::vector<int> tops;
  for (const Neighbour& n : neighbours) {
    MotionField motion = motionOf(current, n.which, layer, s);
    std::vector<float> valid = warpValidity(motion);
    if (!takesPart(n, layer, valid, s)) continue;
    LayerFrame frame = loadLayer(*n.frame, layer, features);
    zero = zero && allZero(frame.color) && allZero(frame.variance);
    loaded.push_back(std::move(frame));
    motions.push_back(std::move(motion));
    valids.push_back(std::move(valid));
    tops.push_back(n.top);
  }
  if (zero) {
    result.color = Planes(current.width(), current.height(), 3);
    result.invalid.assign(current.pixelCount(), 0);
    return result;
  }

  NlMeansFrame& center = input.frames.emplace_back();
  center.color = std::move(first.color);
  center.variance = std::move(first.variance);
  center.features = std::move(first.features);
  for (size_t i = 0; i < loaded.size(); ++i) {
    NlMeansFrame& frame = input.frames.emplace_back();
    frame.color = warpPlanes(loaded[i].color, motions[i], WarpLookup::Bilinear, tops[i]);
    frame.variance = warpPlanes(loaded[i].variance, motions[i], WarpLookup::Bilinear, tops[i]);
    for (size_t g = 0; g < features.size(); ++g)
      frame.features.push_back(warpPlanes(
          loaded[i].features[g], motions[i],
          features[g].kind == FeatureKind::ExactMatch ? WarpLookup::Nearest : WarpLookup::Bilinear, tops[i]));
    frame.valid = std::move(valids[i]);
  }
  // Every frame's fireflies are filtered without their excess, and the excess, spread,
  // is added back as the mean over the frames that hold each pixel: NL-means averages the
  // frames, so each one's light counts as it would have.
  Planes excess;
  bool spread = false;  // some frame had a firefly
  if (s.spreadFireflies) {
    std::vector<float> frames(current.pixelCount(), 0.0f);
    for (size_t i = 0; i < input.frames.size(); ++i) {
      NlMeansFrame& frame = input.frames[i];
      FireflySplit split = splitFireflies(frame.color, frame.variance, frame.valid, surfaceOf(frame), s.fireflies);
      if (i == 0) {
        result.fireflies = split.fireflies;
        excess = Planes(current.width(), current.height(), static_cast<int>(split.excess.channels.size()));
      }
      spread = spread || !split.fireflies.empty();
      for (size_t p = 0; p < frames.size(); ++p) {
        const float weight = frame.valid.empty() ? 1.0f : frame.valid[p];
        frames[p] += weight;
        for (size_t c = 0; c < excess.channels.size(); ++c) excess.channels[c][p] += weight * split.excess.channels[c][p];
      }
    }
    for (size_t c = 0; c < excess.channels.size(); ++c)
      for (size_t p = 0; p < frames.size(); ++p)
        if (frames[p] > 0.0f) excess.channels[c][p] /= frames[p];
  }
  NlMeansSettings settings{s.spatialRadius, s.patch, s.kc, s.kf, s.tau, s.alpha};
  if (input.frames.size() > 1) settings.radius = s.temporalRadius;
  settings.validCentersOnly = s.onlyWithin.has_value();
  NlMeansStats stats;
  result.color = jointNlMeansOnContent(input, settings, &stats, s.onlyWithin ? &*s.onlyWithin : nullptr);
  if (spread)
    for (size_t c = 0; c < result.color.channels.size(); ++c)
      for (size_t p = 0; p < result.color.pixelCount(); ++p) result.color.channels[c][p] += excess.channels[c][p];
  result.invalid = std::move(stats.invalidCenter);
  return result;
}

// The layers to filter.
std::vector<LayerSpec> layersOf(const FrameImage& current, const DenoiseSettings& s) {
  const std::vector<std::string> components = decompositionComponents(current);
  std::vector<LayerSpec> layers;
  if (s.mode == DenoiseMode::ColorOnly) {
    LayerSpec beauty;
    if (!components.empty()) {
      const bool direct = std::find(components.begin(), components.end(), "diffuse_direct") != components.end();
      beauty.featureComponent = direct ? "diffuse_direct" : components.front();
    }
    layers.push_back(beauty);
    return layers;
  }
  if (components.empty())
    throw std::invalid_argument(s.label +
                                ": no \"pathfarm.decomposition\" attribute (not a decomposed render); the "
                                "color-only mode filters such frames");
  for (const std::string& c : components) layers.push_back({c, s.mode == DenoiseMode::Decomposition ? c : "", c + "."});
  return layers;
}

// Rows [first, end) of a motion field, placed in its frame.
MotionField fieldRows(const MotionField& motion, int first, int end) {
  MotionField rows;
  rows.width = motion.width;
  rows.height = end - first;
  rows.top = motion.top + first;
  rows.frameHeight = motion.rowsOfFrame();
  const auto cut = [&](const std::vector<float>& plane) {
    if (plane.empty()) return plane;
    return std::vector<float>(plane.begin() + static_cast<std::ptrdiff_t>(first) * motion.width,
                              plane.begin() + static_cast<std::ptrdiff_t>(end) * motion.width);
  };
  rows.x = cut(motion.x);
  rows.y = cut(motion.y);
  rows.valid = cut(motion.valid);
  return rows;
}

std::string describe(const DenoiseSettings& s, int framesGiven) {
  std::ostringstream text;
  text << "mode=" << denoiseModeName(s.mode) << " frames=" << framesGiven << " r=" << s.spatialRadius << "/"
       << s.temporalRadius << " f=" << s.patch << " kc=" << s.kc << " kf=" << s.kf << " tau=" << s.tau
       << " alpha=" << s.alpha << " depth=" << (s.useDepth ? 1 : 0)
       << " fireflies=" << (s.spreadFireflies ? 1 : 0);
  return text.str();
}

}  // namespace

std::string denoiseModeName(DenoiseMode mode) {
  switch (mode) {
    case DenoiseMode::Decomposition:
      return "decomposition";
    case DenoiseMode::ColorOnly:
      return "color";
    case DenoiseMode::DecompositionWithoutFeatures:
      return "no-features";
  }
  return "decomposition";
}

DenoiseMode parseDenoiseMode(const std::string& name) {
  for (DenoiseMode mode :
       {DenoiseMode::Decomposition, DenoiseMode::ColorOnly, DenoiseMode::DecompositionWithoutFeatures})
    if (denoiseModeName(mode) == name) return mode;
  throw std::invalid_argument("unknown denoise mode \"" + name + "\" (decomposition, color or no-features)");
}

FrameImage denoiseFrame(const FrameImage& current, const FrameImage* previous, const FrameImage* next,
                        const DenoiseSettings& settings) {
  const DenoiseSettings& s = settings;
  if (current.width() <= 0 || current.height() <= 0) throw std::invalid_argument(s.label + ": the frame is empty");
  std::vector<Neighbour> neighbours;
  const DenoiseWindow whole{current.height(), 0, current.height()};
  const DenoiseWindow& rows = s.window ? *s.window : whole;
  if (rows.currentTop < 0 || rows.currentTop + current.height() > rows.frameHeight)
    throw std::logic_error(s.label + ": its rows are not rows of a frame " + std::to_string(rows.frameHeight) +
                           " rows tall");
  if (previous != nullptr) neighbours.push_back({previous, NeighbourFrame::Previous, &s.previousLabel, rows.previousTop});
  if (next != nullptr) neighbours.push_back({next, NeighbourFrame::Next, &s.nextLabel, rows.nextTop});
  // A window's frames hold rows of their frames; whole frames are the same size.
  for (const Neighbour& n : neighbours)
    if (n.frame->width() != current.width() ||
        (s.window ? n.top < 0 || n.top + n.frame->height() > rows.frameHeight : n.frame->height() != current.height()))
      throw std::invalid_argument(*n.label + " is " + std::to_string(n.frame->width()) + "x" +
                                  std::to_string(n.frame->height()) + ", " + s.label + " is " +
                                  std::to_string(current.width()) + "x" + std::to_string(current.height()));

  const std::vector<LayerSpec> layers = layersOf(current, s);

  // Every channel, checked before any work.
  for (const LayerSpec& layer : layers) {
    const std::vector<Buffer> features = featureBuffers(layer, s);
    requireBuffers(current, colorBuffers(layer), s.label);
    requireBuffers(current, features, s.label);
    for (const Neighbour& n : neighbours) {
      const std::string motion = layer.motionPrefix + (n.which == NeighbourFrame::Previous ? "motion_back" : "motion");
      requireChannel(current, motion + ".X", s.label);
      requireChannel(current, motion + ".Y", s.label);
      requireBuffers(*n.frame, colorBuffers(layer), *n.label);
      requireBuffers(*n.frame, features, *n.label);
    }
  }

  // The rows wanted, in the current frame's rows.
  int first = 0, end = current.height();
  if (s.window) {
    first = s.window->first - s.window->currentTop;
    end = s.window->end - s.window->currentTop;
    if (first < 0 || end > current.height() || first >= end)
      throw std::logic_error(s.label + ": the rows wanted are not among the rows given");
  }
  const size_t width = static_cast<size_t>(current.width());
  FrameImage out(current.width(), current.height());
  for (const char* c : kRgbChannels) out.addChannel(c);
  std::vector<uint8_t> skipped(current.pixelCount(), 0);
  size_t fireflies = 0;
  for (const LayerSpec& layer : layers) {
    const LayerResult filtered = filterLayer(current, neighbours, layer, s);
    fireflies += static_cast<size_t>(std::count_if(filtered.fireflies.begin(), filtered.fireflies.end(), [&](size_t p) {
      return p / width >= static_cast<size_t>(first) && p / width < static_cast<size_t>(end);
    }));
    for (size_t p = 0; p < skipped.size(); ++p) skipped[p] |= filtered.invalid[p];
    const std::vector<float>* coverage = coverageOf(current, layer);
    for (size_t c = 0; c < 3; ++c) {
      std::vector<float>& beauty = out.channel(kRgbChannels[c]);
      const std::vector<float>& value = filtered.color.channels[c];
      if (layer.component.empty()) {
        beauty = value;
        continue;
      }
      std::vector<float>& color = out.addChannel(layer.component + ".color." + kRgbChannels[c]);
      const std::vector<float>& reflectance = current.channel(layer.component + ".reflectance." + kRgbChannels[c]);
      for (size_t p = 0; p < color.size(); ++p) {
        const float r = std::isfinite(reflectance[p]) ? reflectance[p] : 0.0f;
        color[p] = modulateIrradiance(value[p], r);
        if (coverage != nullptr) color[p] *= coverageShare((*coverage)[p]);
        beauty[p] += color[p];
      }
    }
  }

  out.attributes() = current.attributes();
  out.attributes()["pathfarm.denoise"] = describe(s, 1 + static_cast<int>(neighbours.size()));
  out.attributes()["pathfarm.denoise_skipped"] =
      std::to_string(std::count(skipped.begin() + static_cast<std::ptrdiff_t>(first * width),
                                skipped.begin() + static_cast<std::ptrdiff_t>(end * width), uint8_t{1}));
  out.attributes()["pathfarm.denoise_fireflies"] = std::to_string(fireflies);
  if (first == 0 && end == current.height()) return out;
  return out.crop(0, first, current.width(), end - first);
}

int denoiseReach(const DenoiseSettings& s) {
  return std::max(s.spatialRadius, s.temporalRadius) + s.patch + (s.spreadFireflies ? fireflyReach(s.fireflies) : 0);
}

std::pair<int, int> denoiseNeighbourRows(const FrameImage& current, NeighbourFrame neighbour,
                                         const DenoiseSettings& settings) {
  const DenoiseSettings& s = settings;
  if (!s.window) throw std::logic_error(s.label + ": neighbour rows are a window's question");
  const int top = s.window->currentTop;
  const int first = std::max(0, s.window->first - denoiseReach(s) - top);
  const int end = std::min(current.height(), s.window->end + denoiseReach(s) - top);
  if (first >= end) return {0, 0};
  int low = s.window->frameHeight, high = 0;
  for (const LayerSpec& layer : layersOf(current, s)) {
    const auto [from, to] = warpSourceRows(fieldRows(motionOf(current, neighbour, layer, s), first, end));
    if (from >= to) continue;
    low = std::min(low, from);
    high = std::max(high, to);
  }
  if (low >= high) return {0, 0};
  return {std::max(0, low), std::min(s.window->frameHeight, high)};
}

std::set<std::string> neighbourLayersReaching(const FrameImage& rows, NeighbourFrame neighbour, int top,
                                              int frameHeight, const DenoiseSettings& settings) {
  std::set<std::string> reaching;
  for (const LayerSpec& layer : layersOf(rows, settings)) {
    MotionField motion = motionTowards(rows, neighbour, layer.motionPrefix, settings.label);
    motion.top = top;
    motion.frameHeight = frameHeight;
    const std::vector<float> valid = warpValidity(motion);
    if (std::any_of(valid.begin(), valid.end(), [](float v) { return v != 0.0f; })) reaching.insert(layer.component);
  }
  return reaching;
}

}  // namespace pathfarm
