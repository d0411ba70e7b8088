#include "postproc/filters/direct_emission.h"

#include <algorithm>
#include <cmath>

#include "image/luminance.h"
#include "postproc/filters/decomposed_frame.h"
#include "renderer/decomposition/effective_irradiance.h"

namespace pathfarm {
namespace {

constexpr const char* kRgb[3] = {"R", "G", "B"};

std::vector<std::string> decomposedComponentsOf(const FrameImage& frame) {
  std::vector<std::string> components = decompositionComponents(frame);
  if (components.empty()) throw std::invalid_argument("the frame has no pathfarm.decomposition attribute");
  return components;
}

// Where a frame's light is changed: the beauty, one component's color (and irradiance).
enum class Target { Beauty, Component };

// Adds `sign` times the component's light to `target` (the beauty, or the component's
// color, clamped at 0, with its irradiance recomputed where the frame has it).
void applyTo(Target target, FrameImage& frame, const FrameImage& emission, const std::string& component, float sign,
             const std::vector<uint8_t>* only) {
  for (const char* c : kRgb) {
    const std::string direct = component + ".direct." + c;
    if (!emission.hasChannel(direct)) continue;
    const std::vector<float>& light = emission.channel(direct);
    if (target == Target::Beauty) {
      std::vector<float>& beauty = frame.channel(c);
      for (size_t p = 0; p < light.size(); ++p)
        if (light[p] != 0.0f && (!only || (*only)[p])) beauty[p] += sign * light[p];
      continue;
    }
    std::vector<float>& color = frame.channel(component + ".color." + c);
    const std::string irradianceName = component + ".irradiance." + c;
    std::vector<float>* irradiance = frame.hasChannel(irradianceName) ? &frame.channel(irradianceName) : nullptr;
    const std::vector<float>* reflectance = irradiance ? &frame.channel(component + ".reflectance." + c) : nullptr;
    for (size_t p = 0; p < light.size(); ++p) {
      if (light[p] == 0.0f || (only && !(*only)[p])) continue;
      color[p] = std::max(0.0f, color[p] + sign * light[p]);
      if (irradiance) (*irradiance)[p] = effectiveIrradiance(color[p], (*reflectance)[p]);
    }
  }
}

// Adds `sign` times the light to the beauty and the components' colors (the channels are
// apart, so the order of the two changes no bit).
void apply(FrameImage& frame, const FrameImage& emission, float sign, const std::vector<uint8_t>* only) {
  for (const std::string& component : decomposedComponentsOf(frame)) {
    applyTo(Target::Beauty, frame, emission, component, sign, only);
    applyTo(Target::Component, frame, emission, component, sign, only);
  }
}

std::vector<float> luminance(const FrameImage& frame, const std::string& prefix) {
  std::vector<float> out(frame.pixelCount(), 0.0f);
  for (int c = 0; c < 3; ++c) {
    if (!frame.hasChannel(prefix + kRgb[c])) continue;
    const std::vector<float>& values = frame.channel(prefix + kRgb[c]);
    for (size_t p = 0; p < out.size(); ++p) out[p] += kLuminanceWeights<float>[c] * values[p];
  }
  return out;
}

}  // namespace

FrameImage directEmissionOf(const FrameImage& frame, const std::string& component) {
  FrameImage emission(frame.width(), frame.height());
  for (const char* c : kRgb) {
    const std::vector<float>& color = frame.channel(component + ".color." + c);
    const std::vector<float>& emitted = frame.channel(component + ".emission." + c);
    if (std::all_of(emitted.begin(), emitted.end(), [](float v) { return v <= 0.0f; })) continue;
    std::vector<float>& light = emission.addChannel(component + ".direct." + c);
    // The light is part of the color; the clamp only guards against rounding.
    for (size_t p = 0; p < light.size(); ++p) light[p] = std::clamp(emitted[p], 0.0f, std::max(0.0f, color[p]));
  }
  return emission;
}

FrameImage directEmissionOf(const FrameImage& frame) {
  FrameImage emission(frame.width(), frame.height());
  for (const std::string& component : decomposedComponentsOf(frame)) emission.paste(directEmissionOf(frame, component), 0, 0);
  return emission;
}

void takeComponentEmission(FrameImage& frame, const std::string& component) {
  applyTo(Target::Component, frame, directEmissionOf(frame, component), component, -1.0f, nullptr);
}

void takeFromBeauty(FrameImage& beauty, const FrameImage& emission, const std::string& component) {
  applyTo(Target::Beauty, beauty, emission, component, -1.0f, nullptr);
}

FrameImage takeDirectEmission(FrameImage& frame) {
  FrameImage emission = directEmissionOf(frame);
  apply(frame, emission, -1.0f, nullptr);
  return emission;
}

void addDirectEmission(FrameImage& frame, const FrameImage& emission, const std::vector<uint8_t>* only) {
  apply(frame, emission, 1.0f, only);
}

std::vector<uint8_t> directLightEdges(const FrameImage& emission, const FrameImage& beauty, float significance) {
  std::vector<float> light(emission.pixelCount(), 0.0f);
  for (const std::string& component : decomposedComponentsOf(beauty)) {
    const std::vector<float> part = luminance(emission, component + ".direct.");
    for (size_t p = 0; p < light.size(); ++p) light[p] += part[p];
  }
  const std::vector<float> total = luminance(beauty, "");
  const int width = emission.width(), height = emission.height();
  std::vector<uint8_t> edges(light.size(), 0);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const size_t p = static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x);
      for (int dy = -1; dy <= 1 && !edges[p]; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int nx = x + dx, ny = y + dy;
          if (nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
          const size_t q = static_cast<size_t>(ny) * static_cast<size_t>(width) + static_cast<size_t>(nx);
          // Judged against what the brighter of the two pixels shows (light included).
          const float scale = std::max({total[p], total[q], 1e-6f});
          if (std::abs(light[p] - light[q]) > significance * scale) {
            edges[p] = 1;
            break;
          }
        }
    }
  return edges;
}

}  // namespace pathfarm
