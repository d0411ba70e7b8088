#include "postproc/interpolation/frame_interpolation.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "postproc/filters/decomposed_frame.h"
#include "postproc/interpolation/forward_splat.h"
#include "renderer/decomposition/effective_irradiance.h"

namespace pathfarm {
namespace {

float luminance(float r, float g, float b) { return 0.2126f * r + 0.7152f * g + 0.0722f * b; }

const std::vector<float>& finiteChannel(const FrameImage& frame, const std::string& name, const std::string& label) {
  if (!frame.hasChannel(name)) throw std::invalid_argument(label + ": missing channel \"" + name + "\"");
  const std::vector<float>& plane = frame.channel(name);
  for (size_t p = 0; p < plane.size(); ++p)
    if (!std::isfinite(plane[p]))
      throw std::invalid_argument(label + ": channel \"" + name + "\" has a non-finite value at pixel (" +
                                  std::to_string(p % static_cast<size_t>(std::max(1, frame.width()))) + ", " +
                                  std::to_string(p / static_cast<size_t>(std::max(1, frame.width()))) + ")");
  return plane;
}

void checkFinite(const std::vector<float>& plane, const std::string& what) {
  for (float v : plane)
    if (!std::isfinite(v)) throw std::invalid_argument(what + " has a non-finite value");
}

void checkField(const MotionField& field, int width, int height, const std::string& what) {
  const size_t pixels = static_cast<size_t>(width) * static_cast<size_t>(height);
  if (field.width != width || field.height != height || field.x.size() != pixels || field.y.size() != pixels ||
      (!field.valid.empty() && field.valid.size() != pixels))
    throw std::invalid_argument(what + " is " + std::to_string(field.width) + "x" + std::to_string(field.height) +
                                " (planes " + std::to_string(field.x.size()) + "/" + std::to_string(field.y.size()) +
                                "), the keyframes " + std::to_string(width) + "x" + std::to_string(height));
  for (size_t p = 0; p < pixels; ++p) {
    const bool valid = field.valid.empty() || field.valid[p] >= 0.5f;
    if ((valid && (!std::isfinite(field.x[p]) || !std::isfinite(field.y[p]))) ||
        (!field.valid.empty() && !std::isfinite(field.valid[p])))
      throw std::invalid_argument(what + " has a non-finite value at pixel " + std::to_string(p));
  }
}

// One layer interpolated on its own: a component, or the beauty for the baseline.
struct Layer {
  std::string name;  // component, or "" for the beauty
  std::array<std::string, 3> color, irradiance;
  std::string depth;
  std::array<std::string, 3> reflectance;  // used with an irradiance motion
  bool irradianceMotion = false;
};

// What a keyframe layer carries.
enum class Carry {
  Color,             // color R G B, irradiance R G B (or the color)
  ColorReflectance,  // color R G B, irradiance R G B, reflectance R G B
  Irradiance,        // irradiance R G B, irradiance R G B
};

struct KeyframeLayer {
  Planes values;  // see Carry
  std::vector<float> depth;     // the depth test's depth (robust: see readLayer)
  std::vector<uint8_t> active;  // the layer's own motion valid here
  std::vector<uint8_t> splats;  // splatted: own motion, or the frame-wide fallback
  std::vector<float> dx, dy;    // full motion to the other keyframe
};

KeyframeLayer readLayer(const FrameImage& frame, const Layer& layer, const MotionField& motion,
                        const MotionField* fallback, const std::string& label, Carry carry = Carry::Color) {
  KeyframeLayer out;
  out.values = Planes(frame.width(), frame.height(), carry == Carry::ColorReflectance ? 9 : 6);
  for (size_t c = 0; c < 3; ++c) {
    if (carry == Carry::Irradiance) {
      out.values.channels[c] = finiteChannel(frame, layer.irradiance[c], label);
      out.values.channels[3 + c] = out.values.channels[c];
      continue;
    }
    out.values.channels[c] = finiteChannel(frame, layer.color[c], label);
    out.values.channels[3 + c] = frame.hasChannel(layer.irradiance[c]) ? finiteChannel(frame, layer.irradiance[c], label)
                                                                       : out.values.channels[c];
    if (carry == Carry::ColorReflectance) out.values.channels[6 + c] = finiteChannel(frame, layer.reflectance[c], label);
  }
  out.depth = finiteChannel(frame, layer.depth, label);
  const size_t pixels = frame.pixelCount();
  // Where the component's own motion is valid its motion is the primary motion (its first
  // non-specular vertex is the primary hit), so its surface is the primary surface: the
  // frame-wide depth.Z, averaged over every sample of the pixel, is a far less noisy
  // estimate of it than `<c>.depth.Z`, averaged over the few samples of that component.
  const std::string validName = layer.name + ".motion_valid.Y";
  if (!layer.name.empty() && frame.hasChannel(validName) && frame.hasChannel("depth.Z")) {
    const std::vector<float>& valid = finiteChannel(frame, validName, label);
    const std::vector<float>& primaryDepth = finiteChannel(frame, "depth.Z", label);
    for (size_t p = 0; p < pixels; ++p)
      if (valid[p] >= 0.5f && primaryDepth[p] > 0.0f) out.depth[p] = primaryDepth[p];
  }
  out.active.assign(pixels, 0);
  for (size_t p = 0; p < pixels; ++p)
    out.active[p] = (motion.valid.empty() || motion.valid[p] >= 0.5f) && std::isfinite(motion.x[p]) &&
                    std::isfinite(motion.y[p]);
  out.dx = motion.x;
  out.dy = motion.y;
  out.splats = out.active;
  if (fallback != nullptr)
    for (size_t p = 0; p < pixels; ++p)
      if (!out.active[p] && (fallback->valid.empty() || fallback->valid[p] >= 0.5f) && std::isfinite(fallback->x[p]) &&
          std::isfinite(fallback->y[p])) {
        out.splats[p] = 1;
        out.dx[p] = fallback->x[p];
        out.dy[p] = fallback->y[p];
      }
  return out;
}

SplatResult splatLayer(const KeyframeLayer& layer, float fraction, const SplatSettings& settings) {
  SplatSource source;
  source.values = &layer.values;
  source.depth = &layer.depth;
  source.active = layer.splats;
  source.dx.resize(layer.dx.size());
  source.dy.resize(layer.dy.size());
  for (size_t p = 0; p < layer.dx.size(); ++p) {
    source.dx[p] = layer.splats[p] ? fraction * layer.dx[p] : 0.0f;
    source.dy[p] = layer.splats[p] ? fraction * layer.dy[p] : 0.0f;
  }
  return forwardSplat(source, settings);
}

// A layer's interpolated values (its first three: the color) and what happened at every pixel.
struct LayerOutcome {
  std::vector<std::vector<float>> color;  // every carried channel
  std::vector<float> depth;
  std::vector<uint8_t> hole, oneSided, changed;
  std::vector<float> change;  // relative irradiance change where both keyframes agree, else -1
};

void markChanged(LayerOutcome& out, const InterpolationSettings& settings, int width, int height);

LayerOutcome combine(const KeyframeLayer& l0, const KeyframeLayer& l1, const SplatResult& a, const SplatResult& b,
                     float s, const InterpolationSettings& settings, int width, int height) {
  const size_t pixels = static_cast<size_t>(width) * static_cast<size_t>(height);
  const size_t channels = l0.values.channels.size();
  LayerOutcome out;
  out.color.assign(channels, std::vector<float>(pixels, 0.0f));
  out.depth.assign(pixels, 0.0f);
  out.hole.assign(pixels, 0);
  out.oneSided.assign(pixels, 0);
  out.changed.assign(pixels, 0);
  std::vector<float>& change = out.change;
  change.assign(pixels, -1.0f);
  // One keyframe alone only when it is nearer by clearly more than the splat's depth
  // tolerance (twice it): within that, the depths are one surface up to noise and both
  // keyframes are averaged.
  const float tol = 1.0f + 2.0f * settings.depthTolerance;
  for (size_t t = 0; t < pixels; ++t) {
    const bool ca = a.covered[t] != 0, cb = b.covered[t] != 0;
    if (!ca && !cb) {
      out.hole[t] = 1;
      for (size_t c = 0; c < channels; ++c)
        out.color[c][t] = (1.0f - s) * l0.values.channels[c][t] + s * l1.values.channels[c][t];
      const float d0 = l0.depth[t], d1 = l1.depth[t];
      out.depth[t] = std::max(d0, d1);
      continue;
    }
    bool useA = ca, useB = cb;
    if (ca && cb) {
      if (a.depth[t] * tol < b.depth[t]) useB = false;
      else if (b.depth[t] * tol < a.depth[t]) useA = false;
    }
    if (useA && useB) {
      for (size_t c = 0; c < channels; ++c)
        out.color[c][t] = (1.0f - s) * a.values.channels[c][t] + s * b.values.channels[c][t];
      const float e0 = luminance(a.values.channels[3][t], a.values.channels[4][t], a.values.channels[5][t]);
      const float e1 = luminance(b.values.channels[3][t], b.values.channels[4][t], b.values.channels[5][t]);
      change[t] = std::fabs(e0 - e1) / std::max(0.5f * (std::fabs(e0) + std::fabs(e1)), settings.irradianceFloor);
      const float da = a.depth[t], db = b.depth[t];
      out.depth[t] = std::isfinite(da) && std::isfinite(db) ? (1.0f - s) * da + s * db : std::min(da, db);
    } else {
      const SplatResult& r = useA ? a : b;
      for (size_t c = 0; c < channels; ++c) out.color[c][t] = r.values.channels[c][t];
      out.depth[t] = r.depth[t];
      out.oneSided[t] = 1;
    }
    if (!std::isfinite(out.depth[t])) out.depth[t] = 0.0f;
  }
  markChanged(out, settings, width, height);
  return out;
}

// The illumination test: a one-sided pixel is `changed` when the largest change within the
// radius exceeds the threshold, or (unknownChangeMasks) no pixel there has a change.
void markChanged(LayerOutcome& out, const InterpolationSettings& settings, int width, int height) {
  const std::vector<float>& change = out.change;
  out.changed.assign(change.size(), 0);
  const int radius = std::max(0, settings.illuminationRadius);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const size_t t = static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x);
      if (!out.oneSided[t]) continue;
      float largest = -1.0f;
      for (int j = std::max(0, y - radius); j <= std::min(height - 1, y + radius); ++j)
        for (int i = std::max(0, x - radius); i <= std::min(width - 1, x + radius); ++i)
          largest = std::max(largest, change[static_cast<size_t>(j) * static_cast<size_t>(width) + static_cast<size_t>(i)]);
      out.changed[t] = (largest < 0.0f && settings.unknownChangeMasks) || largest > settings.illuminationChange;
    }
}

void checkSameLayout(const FrameImage& a, const FrameImage& b, const std::string& labelA, const std::string& labelB) {
  if (a.width() != b.width() || a.height() != b.height())
    throw std::invalid_argument(labelB + " is " + std::to_string(b.width()) + "x" + std::to_string(b.height()) + ", " +
                                labelA + " " + std::to_string(a.width()) + "x" + std::to_string(a.height()));
  if (decompositionComponents(a) != decompositionComponents(b))
    throw std::invalid_argument(labelB + " has another decomposition (pathfarm.decomposition) than " + labelA);
}

// `motion` where it is valid, else `primary` (with its validity).
MotionField withPrimary(const MotionField& motion, const MotionField& primary) {
  MotionField out = primary;
  for (size_t p = 0; p < out.x.size(); ++p)
    if (motion.valid.empty() || motion.valid[p] >= 0.5f) {
      out.x[p] = motion.x[p];
      out.y[p] = motion.y[p];
      if (!out.valid.empty()) out.valid[p] = 1.0f;
    }
  return out;
}

}  // namespace

void addIrradianceFlow(ComponentMotions& motions, const FrameImage& k0, const FrameImage& k1,
                       const FlowSettings& settings) {
  const int width = k0.width(), height = k0.height();
  if (width <= 0 || height <= 0) throw std::invalid_argument("irradiance flow: keyframe 0 is empty");
  checkSameLayout(k0, k1, "keyframe 0", "keyframe 1");
  const std::vector<std::string> components = decompositionComponents(k0);
  FlowSettings logSettings = settings;
  logSettings.logDomain = true;
  const size_t pixels = k0.pixelCount();
  auto irradiance = [&](const FrameImage& frame, const std::string& c, const std::string& label) {
    Planes planes(width, height, 3);
    const char* rgb[3] = {"R", "G", "B"};
    for (size_t i = 0; i < 3; ++i) planes.channels[i] = finiteChannel(frame, c + ".irradiance." + rgb[i], label);
    return planes;
  };
  // The primary motion as the initial guess: 0 where it is invalid.
  auto guess = [&](const MotionField& motion, const std::string& what) {
    checkField(motion, width, height, what);
    FlowField flow(width, height);
    for (size_t p = 0; p < pixels; ++p)
      if (motion.valid.empty() || motion.valid[p] >= 0.5f) {
        flow.dx[p] = motion.x[p];
        flow.dy[p] = motion.y[p];
      }
    return flow;
  };
  auto toMotion = [&](const FlowField& flow) {
    MotionField motion;
    motion.width = width;
    motion.height = height;
    motion.x = flow.dx;
    motion.y = flow.dy;
    motion.valid.assign(pixels, 0.0f);
    for (size_t p = 0; p < pixels; ++p) {
      const float tx = static_cast<float>(p % static_cast<size_t>(width)) + flow.dx[p];
      const float ty = static_cast<float>(p / static_cast<size_t>(width)) + flow.dy[p];
      if (std::isfinite(tx) && std::isfinite(ty) && tx > -0.5f && tx < static_cast<float>(width) - 0.5f &&
          ty > -0.5f && ty < static_cast<float>(height) - 0.5f)
        motion.valid[p] = 1.0f;
    }
    return motion;
  };
  std::vector<std::pair<const std::string, ComponentMotion>*> flowing;
  for (auto& entry : motions.components) {
    if (entry.first.empty()) continue;
    if (std::find(components.begin(), components.end(), entry.first) == components.end())
      throw std::invalid_argument("irradiance flow: the keyframes have no component \"" + entry.first + "\"");
    flowing.push_back(&entry);
  }
  tbb::parallel_for(size_t(0), flowing.size(), [&](size_t i) {
    const std::string& c = flowing[i]->first;
    ComponentMotion& motion = flowing[i]->second;
    const std::string what = "irradiance flow: component \"" + c + "\"";
    const Planes e0 = irradiance(k0, c, "keyframe 0"), e1 = irradiance(k1, c, "keyframe 1");
    const FlowField forward = bootstrappedFlow(e0, e1, guess(motion.forward, what + " forward motion"), logSettings);
    const FlowField backward = bootstrappedFlow(e1, e0, guess(motion.backward, what + " backward motion"), logSettings);
    motion.irradianceForward = toMotion(forward);
    motion.irradianceBackward = toMotion(backward);
    motion.hasIrradianceMotion = true;
  });
}

ComponentMotions concatenatePrimaryMotion(const std::vector<FrameImage>& frames) {
  if (frames.size() < 2)
    throw std::invalid_argument("motion concatenation: needs at least two frames, got " + std::to_string(frames.size()));
  const int width = frames[0].width(), height = frames[0].height();
  if (width <= 0 || height <= 0) throw std::invalid_argument("motion concatenation: frame 0 is empty");
  for (size_t k = 1; k < frames.size(); ++k)
    checkSameLayout(frames[0], frames[k], "frame 0", "frame " + std::to_string(k));
  const size_t pixels = frames[0].pixelCount();
  std::vector<std::string> names = {""};
  for (const std::string& c : decompositionComponents(frames[0])) names.push_back(c);

  auto chain = [&](const std::string& prefix, bool forward) {
    MotionField result;
    result.width = width;
    result.height = height;
    result.x.assign(pixels, 0.0f);
    result.y.assign(pixels, 0.0f);
    result.valid.assign(pixels, 1.0f);
    const size_t n = frames.size();
    for (size_t step = 0; step + 1 < n; ++step) {
      const size_t k = forward ? step : n - 1 - step;
      const std::string label = "motion concatenation: frame " + std::to_string(k);
      const MotionField link =
          motionTowards(frames[k], forward ? NeighbourFrame::Next : NeighbourFrame::Previous, prefix, label);
      const std::string what = label + " layer \"" + prefix + (forward ? "motion" : "motion_back") + "\"";
      checkFinite(link.x, what);
      checkFinite(link.y, what);
      checkFinite(link.valid, label + " channel \"" + prefix + "motion_valid.Y\"");
      MotionField reached;  // frame `front` -> frame k so far
      reached.width = width;
      reached.height = height;
      reached.x = result.x;
      reached.y = result.y;
      const std::vector<float> inside = warpValidity(reached);
      Planes motion(width, height, 2);
      motion.channels[0] = link.x;
      motion.channels[1] = link.y;
      const Planes looked = warpPlanes(motion, reached);
      std::vector<float> linkValid(pixels, 1.0f);
      if (!link.valid.empty()) {
        Planes valid(width, height, 1);
        valid.channels[0] = link.valid;
        linkValid = warpPlanes(valid, reached, WarpLookup::Nearest).channels[0];
      }
      for (size_t p = 0; p < pixels; ++p) {
        if (inside[p] < 0.5f || linkValid[p] < 0.5f) result.valid[p] = 0.0f;
        result.x[p] += looked.channels[0][p];
        result.y[p] += looked.channels[1][p];
      }
    }
    MotionField end = result;
    end.valid.clear();
    const std::vector<float> inside = warpValidity(end);
    for (size_t p = 0; p < pixels; ++p)
      if (inside[p] < 0.5f) result.valid[p] = 0.0f;
    return result;
  };

  ComponentMotions motions;
  for (const std::string& name : names) {
    const std::string prefix = name.empty() ? "" : name + ".";
    motions.components[name] = ComponentMotion{chain(prefix, true), chain(prefix, false)};
  }
  return motions;
}

InterpolationResult interpolateFrameDetailed(const FrameImage& k0, const FrameImage& k1,
                                             const ComponentMotions& motions, float s,
                                             const InterpolationSettings& settings) {
  if (!(s > 0.0f && s < 1.0f))
    throw std::invalid_argument("interpolation: the fraction s must be inside (0, 1), got " + std::to_string(s));
  const int width = k0.width(), height = k0.height();
  if (width <= 0 || height <= 0) throw std::invalid_argument("interpolation: keyframe 0 is empty");
  checkSameLayout(k0, k1, "keyframe 0", "keyframe 1");
  const size_t pixels = k0.pixelCount();

  std::vector<Layer> layers;
  const std::vector<std::string> components = decompositionComponents(k0);
  if (settings.colorOnly) {
    layers.push_back(Layer{"", {"R", "G", "B"}, {"R", "G", "B"}, "depth.Z", {"", "", ""}, false});
  } else {
    if (components.empty())
      throw std::invalid_argument(
          "interpolation: keyframe 0 has no decomposition (attribute pathfarm.decomposition); use the color-only mode");
    for (const std::string& c : components)
      layers.push_back(Layer{c,
                             {c + ".color.R", c + ".color.G", c + ".color.B"},
                             {c + ".irradiance.R", c + ".irradiance.G", c + ".irradiance.B"},
                             c + ".depth.Z",
                             {c + ".reflectance.R", c + ".reflectance.G", c + ".reflectance.B"},
                             false});
  }
  const std::vector<float>* beauty0[3] = {&finiteChannel(k0, "R", "keyframe 0"), &finiteChannel(k0, "G", "keyframe 0"),
                                          &finiteChannel(k0, "B", "keyframe 0")};
  const std::vector<float>* beauty1[3] = {&finiteChannel(k1, "R", "keyframe 1"), &finiteChannel(k1, "G", "keyframe 1"),
                                          &finiteChannel(k1, "B", "keyframe 1")};
  const std::vector<float>* silhouette[2] = {
      k0.hasChannel("silhouette.Y") ? &finiteChannel(k0, "silhouette.Y", "keyframe 0") : nullptr,
      k1.hasChannel("silhouette.Y") ? &finiteChannel(k1, "silhouette.Y", "keyframe 1") : nullptr};

  std::vector<KeyframeLayer> at0(layers.size()), at1(layers.size());
  std::vector<KeyframeLayer> irr0(layers.size()), irr1(layers.size());  // irradiance along its own motion
  for (size_t i = 0; i < layers.size(); ++i) {
    const std::string& name = layers[i].name;
    const std::string what = name.empty() ? "the frame-wide motion (\"\")" : "component \"" + name + "\"";
    const auto found = motions.components.find(name);
    if (found == motions.components.end()) throw std::invalid_argument("interpolation: no motion for " + what);
    checkField(found->second.forward, width, height, "interpolation: forward motion of " + what);
    checkField(found->second.backward, width, height, "interpolation: backward motion of " + what);
    // Untracked components fall back on the frame-wide motion where the caller gave one.
    const auto primary = motions.components.find("");
    const bool fallback = settings.untrackedFollowPrimary && !name.empty() && primary != motions.components.end();
    if (fallback) {
      checkField(primary->second.forward, width, height, "interpolation: forward frame-wide motion");
      checkField(primary->second.backward, width, height, "interpolation: backward frame-wide motion");
    }
    const ComponentMotion& motion = found->second;
    layers[i].irradianceMotion = !name.empty() && motion.hasIrradianceMotion;
    const Carry carry = layers[i].irradianceMotion ? Carry::ColorReflectance : Carry::Color;
    at0[i] = readLayer(k0, layers[i], motion.forward, fallback ? &primary->second.forward : nullptr, "keyframe 0", carry);
    at1[i] = readLayer(k1, layers[i], motion.backward, fallback ? &primary->second.backward : nullptr, "keyframe 1",
                       carry);
    if (layers[i].irradianceMotion) {
      checkField(motion.irradianceForward, width, height, "interpolation: forward irradiance motion of " + what);
      checkField(motion.irradianceBackward, width, height, "interpolation: backward irradiance motion of " + what);
      irr0[i] = readLayer(k0, layers[i], withPrimary(motion.irradianceForward, motion.forward),
                          fallback ? &primary->second.forward : nullptr, "keyframe 0", Carry::Irradiance);
      irr1[i] = readLayer(k1, layers[i], withPrimary(motion.irradianceBackward, motion.backward),
                          fallback ? &primary->second.backward : nullptr, "keyframe 1", Carry::Irradiance);
    }
  }

  const SplatSettings splat{settings.depthTolerance, settings.minCoverage, 0.25f};
  std::vector<LayerOutcome> outcomes(layers.size());
  tbb::parallel_for(size_t(0), layers.size(), [&](size_t i) {
    const SplatResult a = splatLayer(at0[i], s, splat);
    const SplatResult b = splatLayer(at1[i], 1.0f - s, splat);
    outcomes[i] = combine(at0[i], at1[i], a, b, s, settings, width, height);
    if (!layers[i].irradianceMotion) return;
    // The paper's scheme: irradiance along its own motion times reflectance along the primary.
    const SplatResult ea = splatLayer(irr0[i], s, splat);
    const SplatResult eb = splatLayer(irr1[i], 1.0f - s, splat);
    const LayerOutcome e = combine(irr0[i], irr1[i], ea, eb, s, settings, width, height);
    LayerOutcome& o = outcomes[i];
    for (size_t t = 0; t < pixels; ++t) {
      for (size_t c = 0; c < 3; ++c) o.color[c][t] = modulateIrradiance(e.color[c][t], o.color[6 + c][t]);
      o.hole[t] = o.hole[t] || e.hole[t];
      o.oneSided[t] = o.oneSided[t] || e.oneSided[t];
    }
    o.change = e.change;
    markChanged(o, settings, width, height);
  });

  InterpolationResult result;
  result.frame = FrameImage(width, height);
  result.frame.attributes() = k0.attributes();
  std::array<std::vector<float>, 3> beauty;
  for (auto& plane : beauty) plane.assign(pixels, 0.0f);
  for (const LayerOutcome& o : outcomes)
    for (size_t c = 0; c < 3; ++c)
      for (size_t t = 0; t < pixels; ++t) beauty[c][t] += o.color[c][t];

  auto significant = [&](float r, float g, float b, float br, float bg, float bb) {
    return luminance(r, g, b) > std::max(settings.significance * luminance(br, bg, bb), 1e-6f);
  };
  std::vector<uint8_t> hole(pixels, 0), sil(pixels, 0), untracked(pixels, 0), illumination(pixels, 0);
  for (size_t i = 0; i < layers.size(); ++i) {
    const LayerOutcome& o = outcomes[i];
    for (size_t t = 0; t < pixels; ++t) {
      if (!o.hole[t] && !o.oneSided[t]) continue;
      if (!significant(o.color[0][t], o.color[1][t], o.color[2][t], beauty[0][t], beauty[1][t], beauty[2][t])) continue;
      if (o.hole[t]) hole[t] = 1;
      if (o.oneSided[t] && o.changed[t]) illumination[t] = 1;
    }
    // Untracked: significant where the motion is invalid.
    const KeyframeLayer* keys[2] = {&at0[i], &at1[i]};
    const std::vector<float>* const* beauties[2] = {beauty0, beauty1};
    for (int k = 0; k < 2; ++k)
      for (size_t p = 0; p < pixels; ++p) {
        if (keys[k]->active[p]) continue;
        const auto& v = keys[k]->values.channels;
        const auto* const* bt = beauties[k];
        if (significant(v[0][p], v[1][p], v[2][p], (*bt[0])[p], (*bt[1])[p], (*bt[2])[p])) untracked[p] = 1;
      }
  }
  // Silhouettes: where the silhouette pixels of each keyframe land.
  for (int k = 0; k < 2; ++k) {
    if (silhouette[k] == nullptr) continue;
    const float fraction = k == 0 ? s : 1.0f - s;
    for (size_t p = 0; p < pixels; ++p) {
      if ((*silhouette[k])[p] <= 0.5f) continue;
      const int px = static_cast<int>(p % static_cast<size_t>(width)), py = static_cast<int>(p / static_cast<size_t>(width));
      bool landed = false;
      for (size_t i = 0; i < layers.size(); ++i) {
        const KeyframeLayer& l = k == 0 ? at0[i] : at1[i];
        if (!l.active[p]) continue;
        const int tx = static_cast<int>(std::lround(static_cast<float>(px) + fraction * l.dx[p]));
        const int ty = static_cast<int>(std::lround(static_cast<float>(py) + fraction * l.dy[p]));
        if (tx < 0 || tx >= width || ty < 0 || ty >= height) continue;
        sil[static_cast<size_t>(ty) * static_cast<size_t>(width) + static_cast<size_t>(tx)] = 1;
        landed = true;
      }
      if (!landed) sil[p] = 1;
    }
  }

  result.mask.assign(pixels, 0);
  result.holes = hole;
  std::vector<float>& rerender = result.frame.addChannel("rerender.Y");
  size_t masked = 0;
  for (size_t t = 0; t < pixels; ++t) {
    result.holePixels += hole[t];
    result.silhouettePixels += sil[t];
    result.untrackedPixels += untracked[t];
    result.illuminationPixels += illumination[t];
    result.mask[t] = hole[t] || sil[t] || untracked[t] || illumination[t];
    rerender[t] = result.mask[t];
    masked += result.mask[t];
  }
  result.rerenderRate = static_cast<double>(masked) / static_cast<double>(pixels);
  const char* rgb[3] = {"R", "G", "B"};
  for (size_t c = 0; c < 3; ++c) result.frame.addChannel(rgb[c]) = beauty[c];
  if (!settings.colorOnly) {
    for (size_t i = 0; i < layers.size(); ++i) {
      for (size_t c = 0; c < 3; ++c) result.frame.addChannel(layers[i].color[c]) = outcomes[i].color[c];
      result.frame.addChannel(layers[i].depth) = outcomes[i].depth;
    }
  }
  char rate[32];
  std::snprintf(rate, sizeof rate, "%.6f", result.rerenderRate);
  result.frame.attributes()["pathfarm.rerender_rate"] = rate;
  result.frame.attributes()["pathfarm.interpolation_fraction"] = std::to_string(s);
  if (settings.colorOnly) {
    result.frame.attributes().erase("pathfarm.decomposition");
    result.frame.attributes()["pathfarm.interpolation_mode"] = "color-only";
  }
  if (!settings.colorOnly) result.frame.attributes()["pathfarm.interpolation_mode"] = "per-component";
  return result;
}

FrameImage interpolateFrame(const FrameImage& k0, const FrameImage& k1, const ComponentMotions& motions, float s,
                            const InterpolationSettings& settings) {
  return interpolateFrameDetailed(k0, k1, motions, s, settings).frame;
}

}  // namespace pathfarm
