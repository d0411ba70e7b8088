#include "postproc/interpolation/frame_interpolation.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "image/luminance.h"
#include "postproc/filters/decomposed_frame.h"
#include "postproc/interpolation/forward_splat.h"
#include "postproc/interpolation/interpolation_input.h"
#include "renderer/decomposition/effective_irradiance.h"

namespace pathfarm {
namespace {

// One layer interpolated on its own: a component, or the beauty for the baseline.
struct Layer {
  std::string name;  // component, or "" for the beauty
  std::array<std::string, 3> color, irradiance;
  std::string depth;
  std::array<std::string, 3> reflectance;  // used with an irradiance motion or an own reflectance
  bool irradianceMotion = false;
  bool specular = false;  // isSpecularComponent
  // The in-between frame's own reflectance of the layer, when the caller gave one
  // (LayeredKeyframes::inBetween) and both it and the keyframes have it; else null.
  std::array<const std::vector<float>*, 3> ownReflectance{};
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
  // Where a non-specular component's own motion is valid its motion is the primary motion
  // (its first non-specular vertex is the primary hit), so its surface is the primary
  // surface: the frame-wide depth.Z, averaged over every sample of the pixel, is a far less
  // noisy estimate of it than `<c>.depth.Z`, averaged over the few samples of that
  // component. A specular component's surface lies beyond the mirror or glass the camera
  // hits: its valid motion is the manifold walk's, and depth.Z is the glass's.
  const std::string validName = layer.name + ".motion_valid.Y";
  if (!layer.name.empty() && !layer.specular && frame.hasChannel(validName) && frame.hasChannel("depth.Z")) {
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

// The depth each keyframe's pixel has at the in-between instant, for the depth tests: the
// camera moves, so a surface near it is nearer or farther in one keyframe than in the
// other by more than the tests' tolerance, and the keyframe it is nearer in would win it
// alone. A pixel p of keyframe k whose motion leads to q in the other keyframe, whose
// motion leads back within a pixel of p (the same surface, not an occluder), takes its
// depth blended with the other keyframe's at q, as the instant lies between them
// (`fraction` from keyframe 0); elsewhere its own depth.
std::array<std::vector<float>, 2> depthsAtInstant(const std::array<KeyframeLayer, 2>& from, float fraction) {
  std::array<std::vector<float>, 2> depths{from[0].depth, from[1].depth};
  const int width = from[0].values.width, height = from[0].values.height;
  const size_t W = static_cast<size_t>(width);
  for (size_t k = 0; k < 2; ++k) {
    const KeyframeLayer& own = from[k];
    const KeyframeLayer& other = from[1 - k];
    const float towardsOther = k == 0 ? fraction : 1.0f - fraction;
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        const size_t p = static_cast<size_t>(y) * W + static_cast<size_t>(x);
        if (!own.splats[p] || !(own.depth[p] > 0.0f)) continue;
        const int qx = static_cast<int>(std::lround(static_cast<float>(x) + own.dx[p]));
        const int qy = static_cast<int>(std::lround(static_cast<float>(y) + own.dy[p]));
        if (qx < 0 || qx >= width || qy < 0 || qy >= height) continue;
        const size_t q = static_cast<size_t>(qy) * W + static_cast<size_t>(qx);
        if (!other.splats[q] || !(other.depth[q] > 0.0f)) continue;
        const float backX = static_cast<float>(qx) + other.dx[q] - static_cast<float>(x);
        const float backY = static_cast<float>(qy) + other.dy[q] - static_cast<float>(y);
        if (backX * backX + backY * backY > 1.0f) continue;
        depths[k][p] = (1.0f - towardsOther) * own.depth[p] + towardsOther * other.depth[q];
      }
  }
  return depths;
}

SplatResult splatLayer(const KeyframeLayer& layer, const std::vector<float>& depth, float fraction,
                       const SplatSettings& settings) {
  SplatSource source;
  source.values = &layer.values;
  source.depth = &depth;
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

// The layers interpolated on their own: every component, or the beauty alone (colorOnly).
std::vector<Layer> layersOf(const FrameImage& k0, const InterpolationSettings& settings) {
  std::vector<Layer> layers;
  const std::vector<std::string> components = decompositionComponents(k0);
  if (settings.colorOnly) {
    layers.push_back(Layer{"", {"R", "G", "B"}, {"R", "G", "B"}, "depth.Z", {"", "", ""}, false});
    return layers;
  }
  if (components.empty())
    throw std::invalid_argument(
        "interpolation: keyframe 0 has no decomposition (attribute pathfarm.decomposition); use the color-only mode");
  for (const std::string& c : components)
    layers.push_back(Layer{c,
                           {c + ".color.R", c + ".color.G", c + ".color.B"},
                           {c + ".irradiance.R", c + ".irradiance.G", c + ".irradiance.B"},
                           c + ".depth.Z",
                           {c + ".reflectance.R", c + ".reflectance.G", c + ".reflectance.B"},
                           false,
                           isSpecularComponent(k0, c)});
  return layers;
}

using BeautyPlanes = std::array<const std::vector<float>*, 3>;  // R, G, B

BeautyPlanes finiteBeauty(const FrameImage& frame, const std::string& label) {
  return {&finiteChannel(frame, "R", label), &finiteChannel(frame, "G", label), &finiteChannel(frame, "B", label)};
}

// One layer as the keyframes carry it towards each other, [0] from K0 and [1] from K1.
struct LayerKeyframes {
  std::array<KeyframeLayer, 2> primary;     // along the layer's motion
  std::array<KeyframeLayer, 2> irradiance;  // the irradiance along its own motion (Layer::irradianceMotion)
};

// The in-between frame's reflectance of `layer` where both it and keyframe `k0` have one.
std::array<const std::vector<float>*, 3> ownReflectanceOf(const FrameImage* inBetween, const FrameImage& k0,
                                                          const Layer& layer) {
  if (inBetween == nullptr || layer.name.empty()) return {};
  std::array<const std::vector<float>*, 3> own{};
  for (size_t c = 0; c < 3; ++c) {
    if (!inBetween->hasChannel(layer.reflectance[c]) || !k0.hasChannel(layer.reflectance[c])) return {};
    own[c] = &finiteChannel(*inBetween, layer.reflectance[c], "the in-between frame's features");
  }
  return own;
}

// Checks the layer's motions and reads it from both keyframes; sets layer.irradianceMotion
// and layer.ownReflectance. `primary`: the frame-wide motion, or null.
LayerKeyframes readKeyframes(const FrameImage& k0, const FrameImage& k1, Layer& layer, const ComponentMotion& motion,
                             const ComponentMotion* primary, const FrameImage* inBetween,
                             const InterpolationSettings& settings) {
  const int width = k0.width(), height = k0.height();
  const std::string& name = layer.name;
  const std::string what = name.empty() ? "the frame-wide motion (\"\")" : "component \"" + name + "\"";
  checkField(motion.forward, width, height, "interpolation: forward motion of " + what);
  checkField(motion.backward, width, height, "interpolation: backward motion of " + what);
  // Untracked components fall back on the frame-wide motion where the caller gave one.
  const bool fallback = settings.untrackedFollowPrimary && !name.empty() && primary != nullptr;
  if (fallback) {
    checkField(primary->forward, width, height, "interpolation: forward frame-wide motion");
    checkField(primary->backward, width, height, "interpolation: backward frame-wide motion");
  }
  layer.irradianceMotion = !name.empty() && motion.hasIrradianceMotion;
  layer.ownReflectance = ownReflectanceOf(inBetween, k0, layer);
  const bool ownReflectance = layer.ownReflectance[0] != nullptr;
  const Carry carry = layer.irradianceMotion || ownReflectance ? Carry::ColorReflectance : Carry::Color;
  LayerKeyframes keys;
  keys.primary[0] =
      readLayer(k0, layer, motion.forward, fallback ? &primary->forward : nullptr, "keyframe 0", carry);
  keys.primary[1] =
      readLayer(k1, layer, motion.backward, fallback ? &primary->backward : nullptr, "keyframe 1", carry);
  if (layer.irradianceMotion) {
    checkField(motion.irradianceForward, width, height, "interpolation: forward irradiance motion of " + what);
    checkField(motion.irradianceBackward, width, height, "interpolation: backward irradiance motion of " + what);
    keys.irradiance[0] = readLayer(k0, layer, withPrimary(motion.irradianceForward, motion.forward),
                                   fallback ? &primary->forward : nullptr, "keyframe 0", Carry::Irradiance);
    keys.irradiance[1] = readLayer(k1, layer, withPrimary(motion.irradianceBackward, motion.backward),
                                   fallback ? &primary->backward : nullptr, "keyframe 1", Carry::Irradiance);
  }
  return keys;
}

// 1 where the splatted reflectance (channels 6..8 of `out`) has an edge within a pixel:
// its luminance over the 3x3 neighbourhood spans more than settings.textureEdge relative.
std::vector<uint8_t> textureEdges(const LayerOutcome& out, const InterpolationSettings& settings, int width,
                                  int height) {
  const size_t pixels = static_cast<size_t>(width) * static_cast<size_t>(height);
  std::vector<float> level(pixels);
  for (size_t t = 0; t < pixels; ++t) level[t] = luminance(out.color[6][t], out.color[7][t], out.color[8][t]);
  std::vector<uint8_t> edge(pixels, 0);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      float low = std::numeric_limits<float>::infinity(), high = 0.0f;
      for (int v = std::max(0, y - 1); v <= std::min(height - 1, y + 1); ++v)
        for (int u = std::max(0, x - 1); u <= std::min(width - 1, x + 1); ++u) {
          const float l = level[static_cast<size_t>(v) * static_cast<size_t>(width) + static_cast<size_t>(u)];
          low = std::min(low, l);
          high = std::max(high, l);
        }
      edge[static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)] =
          high > (1.0f + settings.textureEdge) * std::max(low, kReflectanceGuard);
    }
  return edge;
}

// The layer at fraction s: both keyframes splatted towards it and combined.
LayerOutcome interpolateLayer(const Layer& layer, const LayerKeyframes& keys, float s,
                              const InterpolationSettings& settings, int width, int height) {
  const SplatSettings splat{settings.depthTolerance, settings.minCoverage, 0.25f};
  // Each pair of splats lives only until it is combined: at 4K a splat is a dozen planes of
  // 33 MB, and a worker interpolates two layers at once.
  const auto splattedAndCombined = [&](const std::array<KeyframeLayer, 2>& from) {
    const std::array<std::vector<float>, 2> depths = depthsAtInstant(from, s);
    const SplatResult a = splatLayer(from[0], depths[0], s, splat);
    const SplatResult b = splatLayer(from[1], depths[1], 1.0f - s, splat);
    return combine(from[0], from[1], a, b, s, settings, width, height);
  };
  LayerOutcome out = splattedAndCombined(keys.primary);
  const bool ownReflectance = layer.ownReflectance[0] != nullptr;
  if (!layer.irradianceMotion && !ownReflectance) return out;
  // The paper's scheme: irradiance along its own motion times reflectance along the primary.
  // Within a pixel of a texture edge, the in-between frame's own reflectance instead: moved
  // from the keyframes, an edge is blurred by the splat and put where the motion puts it.
  // Elsewhere the keyframes' reflectance is as right and far less noisy than a few samples'
  // (a coated surface's share of the diffuse lobe), and used alone it flickers from frame
  // to frame. Both must be above the guard, so that the irradiance is an irradiance.
  const LayerOutcome e = layer.irradianceMotion ? splattedAndCombined(keys.irradiance) : LayerOutcome{};
  const std::vector<std::vector<float>>& irradiance = layer.irradianceMotion ? e.color : out.color;
  const size_t pixels = static_cast<size_t>(width) * static_cast<size_t>(height);
  const std::vector<uint8_t> edges = ownReflectance ? textureEdges(out, settings, width, height) : std::vector<uint8_t>{};
  for (size_t t = 0; t < pixels; ++t) {
    for (size_t c = 0; c < 3; ++c) {
      const float splatted = out.color[6 + c][t];
      const bool own = ownReflectance && edges[t] && splatted >= kReflectanceGuard && (*layer.ownReflectance[c])[t] >= kReflectanceGuard;
      if (own) out.color[c][t] = irradiance[3 + c][t] * (*layer.ownReflectance[c])[t];
      else if (layer.irradianceMotion) out.color[c][t] = modulateIrradiance(irradiance[3 + c][t], splatted);
    }
  }
  if (!layer.irradianceMotion) return out;
  for (size_t t = 0; t < pixels; ++t) {
    out.hole[t] = out.hole[t] || e.hole[t];
    out.oneSided[t] = out.oneSided[t] || e.oneSided[t];
  }
  out.change = e.change;
  markChanged(out, settings, width, height);
  return out;
}

// The interpolated beauty R, G, B: the sum of the layers' colors.
std::array<std::vector<float>, 3> summedBeauty(const std::vector<LayerOutcome>& outcomes, size_t pixels) {
  std::array<std::vector<float>, 3> beauty;
  for (auto& plane : beauty) plane.assign(pixels, 0.0f);
  for (const LayerOutcome& o : outcomes)
    for (size_t c = 0; c < 3; ++c)
      for (size_t t = 0; t < pixels; ++t) beauty[c][t] += o.color[c][t];
  return beauty;
}

// The parts of the re-render mask (frame_interpolation.h), a byte per pixel each.
struct RerenderCauses {
  explicit RerenderCauses(size_t pixels)
      : hole(pixels, 0), silhouette(pixels, 0), untracked(pixels, 0), illumination(pixels, 0) {}

  std::vector<uint8_t> hole, silhouette, untracked, illumination;
};

bool significant(float r, float g, float b, float br, float bg, float bb, const InterpolationSettings& settings) {
  return luminance(r, g, b) > std::max(settings.significance * luminance(br, bg, bb), 1e-6f);
}

// Holes and illumination changes: a layer's hole or one-sided pixels where it is significant.
void markHolesAndIllumination(const LayerOutcome& o, const std::array<std::vector<float>, 3>& beauty,
                              const InterpolationSettings& settings, RerenderCauses& causes) {
  for (size_t t = 0; t < o.hole.size(); ++t) {
    if (!o.hole[t] && !o.oneSided[t]) continue;
    if (!significant(o.color[0][t], o.color[1][t], o.color[2][t], beauty[0][t], beauty[1][t], beauty[2][t], settings))
      continue;
    if (o.hole[t]) causes.hole[t] = 1;
    if (o.oneSided[t] && o.changed[t]) causes.illumination[t] = 1;
  }
}

// Untracked: a keyframe's layer significant (against that keyframe's beauty) where its
// motion is invalid.
void markUntracked(const KeyframeLayer& key, const BeautyPlanes& beauty, const InterpolationSettings& settings,
                   std::vector<uint8_t>& untracked) {
  const auto& v = key.values.channels;
  for (size_t p = 0; p < key.active.size(); ++p) {
    if (key.active[p]) continue;
    if (significant(v[0][p], v[1][p], v[2][p], (*beauty[0])[p], (*beauty[1])[p], (*beauty[2])[p], settings))
      untracked[p] = 1;
  }
}

// Silhouettes: where the silhouette pixels of keyframe k land at `fraction` of the way
// along each layer's valid motion (the pixel itself where no layer's is valid). One layer
// at a time: its targets marked in `targets`, and in `landed` the silhouette pixels it
// carried somewhere.
void markSilhouetteTargets(const std::vector<float>& silhouette, const KeyframeLayer& layer, float fraction, int width,
                           int height, std::vector<uint8_t>& targets, std::vector<uint8_t>& landed) {
  for (size_t p = 0; p < silhouette.size(); ++p) {
    if (silhouette[p] <= 0.5f || !layer.active[p]) continue;
    const int px = static_cast<int>(p % static_cast<size_t>(width)), py = static_cast<int>(p / static_cast<size_t>(width));
    // The nearest pixel, from the displacement alone (as the splat's footprints are).
    const float mx = std::floor(fraction * layer.dx[p] + 0.5f), my = std::floor(fraction * layer.dy[p] + 0.5f);
    if (!(std::abs(mx) <= static_cast<float>(width) && std::abs(my) <= static_cast<float>(height))) continue;
    const int tx = px + static_cast<int>(mx), ty = py + static_cast<int>(my);
    if (tx < 0 || tx >= width || ty < 0 || ty >= height) continue;
    targets[static_cast<size_t>(ty) * static_cast<size_t>(width) + static_cast<size_t>(tx)] = 1;
    landed[p] = 1;
  }
}

// What a layer leaves for the re-render mask besides its outcome, found while its keyframe
// buffers are at hand.
struct LayerMarks {
  std::vector<uint8_t> untracked;
  std::array<std::vector<uint8_t>, 2> silhouetteTargets, silhouetteLanded;  // per keyframe
};

// The mask, its counts per cause and rate, and its channel `rerender.Y`.
void addRerenderMask(InterpolationResult& result, const RerenderCauses& causes) {
  const size_t pixels = causes.hole.size();
  result.mask.assign(pixels, 0);
  result.holes = causes.hole;
  result.silhouettes = causes.silhouette;
  result.untracked = causes.untracked;
  result.illumination = causes.illumination;
  std::vector<float>& rerender = result.frame.addChannel("rerender.Y");
  size_t masked = 0;
  for (size_t t = 0; t < pixels; ++t) {
    result.holePixels += causes.hole[t];
    result.silhouettePixels += causes.silhouette[t];
    result.untrackedPixels += causes.untracked[t];
    result.illuminationPixels += causes.illumination[t];
    result.mask[t] = causes.hole[t] || causes.silhouette[t] || causes.untracked[t] || causes.illumination[t];
    rerender[t] = result.mask[t];
    masked += result.mask[t];
  }
  result.rerenderRate = static_cast<double>(masked) / static_cast<double>(pixels);
}

// The beauty, the layers' colors and depths (not in the color-only mode) and the attributes.
void addInterpolatedFrame(FrameImage& frame, const std::array<std::vector<float>, 3>& beauty,
                          const std::vector<Layer>& layers, const std::vector<LayerOutcome>& outcomes, float s,
                          double rerenderRate, const InterpolationSettings& settings) {
  const char* rgb[3] = {"R", "G", "B"};
  for (size_t c = 0; c < 3; ++c) frame.addChannel(rgb[c]) = beauty[c];
  if (!settings.colorOnly) {
    for (size_t i = 0; i < layers.size(); ++i) {
      for (size_t c = 0; c < 3; ++c) frame.addChannel(layers[i].color[c]) = outcomes[i].color[c];
      frame.addChannel(layers[i].depth) = outcomes[i].depth;
    }
  }
  char rate[32];
  std::snprintf(rate, sizeof rate, "%.6f", rerenderRate);
  frame.attributes()["pathfarm.rerender_rate"] = rate;
  frame.attributes()["pathfarm.interpolation_fraction"] = std::to_string(s);
  if (settings.colorOnly) {
    frame.attributes().erase("pathfarm.decomposition");
    frame.attributes()["pathfarm.interpolation_mode"] = "color-only";
  }
  if (!settings.colorOnly) frame.attributes()["pathfarm.interpolation_mode"] = "per-component";
}

}  // namespace

InterpolationResult interpolateFrameDetailed(const LayeredKeyframes& keys, float s,
                                             const InterpolationSettings& settings) {
  if (!(s > 0.0f && s < 1.0f))
    throw std::invalid_argument("interpolation: the fraction s must be inside (0, 1), got " + std::to_string(s));
  if (keys.frameWide[0] == nullptr || keys.frameWide[1] == nullptr)
    throw std::invalid_argument("interpolation: a keyframe is missing");
  const FrameImage &k0 = *keys.frameWide[0], &k1 = *keys.frameWide[1];
  const int width = k0.width(), height = k0.height();
  if (width <= 0 || height <= 0) throw std::invalid_argument("interpolation: keyframe 0 is empty");
  checkSameLayout(k0, k1, "keyframe 0", "keyframe 1");
  if (keys.inBetween != nullptr && (keys.inBetween->width() != width || keys.inBetween->height() != height))
    throw std::invalid_argument("interpolation: the in-between frame's features are " +
                                std::to_string(keys.inBetween->width()) + "x" + std::to_string(keys.inBetween->height()) +
                                ", the keyframes " + std::to_string(width) + "x" + std::to_string(height));
  const size_t pixels = k0.pixelCount();

  std::vector<Layer> layers = layersOf(k0, settings);
  const BeautyPlanes keyBeauty[2] = {finiteBeauty(k0, "keyframe 0"), finiteBeauty(k1, "keyframe 1")};
  const std::vector<float>* silhouette[2] = {
      k0.hasChannel("silhouette.Y") ? &finiteChannel(k0, "silhouette.Y", "keyframe 0") : nullptr,
      k1.hasChannel("silhouette.Y") ? &finiteChannel(k1, "silhouette.Y", "keyframe 1") : nullptr};
  // Each layer's keyframe buffers (copies of a dozen planes per keyframe) live only while
  // the layer is interpolated, and its channels of the keyframes only while they are read:
  // held for every layer at once they were most of a 1080p interpolation's memory.
  std::vector<LayerOutcome> outcomes(layers.size());
  std::vector<LayerMarks> marks(layers.size());
  tbb::parallel_for(size_t(0), layers.size(), [&](size_t i) {
    const LayerKeyframes keyframes = [&] {
      const KeyframeComponent component = keys.component(layers[i].name);
      for (const auto& frame : component.frames)
        if (!frame || frame->width() != width || frame->height() != height || !component.motion)
          throw std::invalid_argument("interpolation: layer \"" + layers[i].name +
                                      "\" of a keyframe is missing or of another size");
      return readKeyframes(*component.frames[0], *component.frames[1], layers[i], *component.motion,
                           keys.frameWideMotion, keys.inBetween, settings);
    }();
    outcomes[i] = interpolateLayer(layers[i], keyframes, s, settings, width, height);
    outcomes[i].color.resize(3);  // the irradiance and reflectance it carried are combined already
    LayerMarks& m = marks[i];
    m.untracked.assign(pixels, 0);
    for (size_t k = 0; k < 2; ++k) {
      markUntracked(keyframes.primary[k], keyBeauty[k], settings, m.untracked);
      if (silhouette[k] == nullptr) continue;
      m.silhouetteTargets[k].assign(pixels, 0);
      m.silhouetteLanded[k].assign(pixels, 0);
      markSilhouetteTargets(*silhouette[k], keyframes.primary[k], k == 0 ? s : 1.0f - s, width, height,
                            m.silhouetteTargets[k], m.silhouetteLanded[k]);
    }
  });

  const std::array<std::vector<float>, 3> beauty = summedBeauty(outcomes, pixels);

  RerenderCauses causes(pixels);
  for (size_t i = 0; i < layers.size(); ++i) {
    markHolesAndIllumination(outcomes[i], beauty, settings, causes);
    for (size_t p = 0; p < pixels; ++p) causes.untracked[p] |= marks[i].untracked[p];
  }
  for (size_t k = 0; k < 2; ++k) {
    if (silhouette[k] == nullptr) continue;
    for (size_t p = 0; p < pixels; ++p) {
      bool landed = false;
      for (const LayerMarks& m : marks) {
        causes.silhouette[p] |= m.silhouetteTargets[k][p];
        landed = landed || m.silhouetteLanded[k][p];
      }
      if ((*silhouette[k])[p] > 0.5f && !landed) causes.silhouette[p] = 1;
    }
  }

  InterpolationResult result;
  result.frame = FrameImage(width, height);
  result.frame.attributes() = k0.attributes();
  addRerenderMask(result, causes);
  addInterpolatedFrame(result.frame, beauty, layers, outcomes, s, result.rerenderRate, settings);
  return result;
}

LayeredKeyframes wholeKeyframes(const FrameImage& k0, const FrameImage& k1, const ComponentMotions& motions) {
  // Every layer reads the whole frames, which the caller holds.
  const auto held = [](const FrameImage& frame) {
    return std::shared_ptr<const FrameImage>(std::shared_ptr<void>(), &frame);
  };
  LayeredKeyframes keys;
  keys.frameWide = {&k0, &k1};
  keys.component = [&k0, &k1, &motions, held](const std::string& name) {
    const auto found = motions.components.find(name);
    if (found == motions.components.end())
      throw std::invalid_argument("interpolation: no motion for " +
                                  (name.empty() ? "the frame-wide motion (\"\")" : "component \"" + name + "\""));
    return KeyframeComponent{{held(k0), held(k1)},
                             std::shared_ptr<const ComponentMotion>(std::shared_ptr<void>(), &found->second)};
  };
  const auto primary = motions.components.find("");
  keys.frameWideMotion = primary != motions.components.end() ? &primary->second : nullptr;
  return keys;
}

InterpolationResult interpolateFrameDetailed(const FrameImage& k0, const FrameImage& k1,
                                             const ComponentMotions& motions, float s,
                                             const InterpolationSettings& settings) {
  return interpolateFrameDetailed(wholeKeyframes(k0, k1, motions), s, settings);
}

FrameImage interpolateFrame(const FrameImage& k0, const FrameImage& k1, const ComponentMotions& motions, float s,
                            const InterpolationSettings& settings) {
  return interpolateFrameDetailed(k0, k1, motions, s, settings).frame;
}

}  // namespace pathfarm
