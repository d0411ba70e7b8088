#include "renderer/decomposition/decomposed_film.h"

#include <bit>
#include <cmath>

#include "renderer/decomposition/effective_irradiance.h"

namespace pathfarm {
namespace {

// Two samples' motions conflict when they differ by more than half a pixel, or when one
// of them has none (its point leaves the view).
bool conflicting(const std::optional<Vec2f>& a, const std::optional<Vec2f>& b) {
  if (!a || !b) return a.has_value() != b.has_value();
  return std::hypot(a->x - b->x, a->y - b->y) > 0.5f;
}

void addTo(double* sums, Rgb v) {
  sums[0] += v.r;
  sums[1] += v.g;
  sums[2] += v.b;
}

}  // namespace

DecomposedFilm::DecomposedFilm(FrameImage& image, const Decomposition& decomposition) {
  const auto add = [&](const std::string& name) { return image.addChannel(name).data(); };
  const auto addRgb = [&](const std::string& prefix, float* (&out)[3]) {
    out[0] = add(prefix + ".R");
    out[1] = add(prefix + ".G");
    out[2] = add(prefix + ".B");
  };
  const auto addXyz = [&](const std::string& prefix, float* (&out)[3]) {
    out[0] = add(prefix + ".X");
    out[1] = add(prefix + ".Y");
    out[2] = add(prefix + ".Z");
  };
  const auto addXy = [&](const std::string& prefix, float* (&out)[2]) {
    out[0] = add(prefix + ".X");
    out[1] = add(prefix + ".Y");
  };
  for (int k = 0; k < decomposition.size(); ++k) {
    const std::string name = decomposition.name(k);
    ComponentChannels c{};
    addRgb(name + ".color", c.color);
    addRgb(name + ".variance", c.variance);
    addRgb(name + ".reflectance", c.reflectance);
    addRgb(name + ".irradiance", c.irradiance);
    addXyz(name + ".normal", c.normal);
    c.objectId = add(name + ".objectid.Y");
    c.primitive = add(name + ".primid.Y");
    addXy(name + ".uv", c.uv);
    c.depth = add(name + ".depth.Z");
    c.coverage = add(name + ".coverage.Y");
    addRgb(name + ".emission", c.direct);
    addXy(name + ".motion", c.motion);
    addXy(name + ".motion_back", c.motionBack);
    c.motionValid = add(name + ".motion_valid.Y");
    components_.push_back(c);
  }
  depth_ = add("depth.Z");
  addXy("motion", motion_);
  addXy("motion_back", motionBack_);
  silhouette_ = add("silhouette.Y");
  movingCaustic_ = add("moving_caustic.Y");
}

DecomposedFilm::Pixel::Pixel(int components) : components_(static_cast<size_t>(components)) {}

void DecomposedFilm::Pixel::add(const SampleComponents& sample, const SampleExtras& extras) {
  ++samples_;
  const bool moving = extras.motionSampled && extras.motion && extras.motionBack;
  // A component the sample did not touch would add zeros.
  for (uint32_t bits = sample.touched; bits != 0; bits &= bits - 1) {
    const auto k = static_cast<size_t>(std::countr_zero(bits));
    Component& c = components_[k];
    const Rgb color = sample.color[k];
    for (int i = 0; i < 3; ++i) {
      c.color[i] += color[i];
      c.colorSquared[i] += static_cast<double>(color[i]) * color[i];
    }
    addTo(c.direct, sample.direct[k]);
    if (!sample.hasFeatures(k)) continue;
    const SampleComponents::Features& f = sample.features[k];
    if (c.features++ == 0) {
      c.objectId = f.objectId;  // ids cannot be averaged: the first sample's
      c.primitive = f.primitive;
    }
    addTo(c.reflectance, f.reflectance);
    c.normal[0] += f.normal.x;
    c.normal[1] += f.normal.y;
    c.normal[2] += f.normal.z;
    c.uv[0] += f.uv.x;
    c.uv[1] += f.uv.y;
    c.depth += f.depth;
    // Primary motion belongs to a component whose first non-specular vertex is what
    // the camera sees; through a mirror or glass it does not (that is the manifold walk's).
    if (moving && extras.hit && f.position == extras.position) {
      ++c.moving;
      c.motion[0] += extras.motion->x;
      c.motion[1] += extras.motion->y;
      c.motionBack[0] += extras.motionBack->x;
      c.motionBack[1] += extras.motionBack->y;
    }
  }
  movingCaustic_ += sample.movingCaustic.luminance();
  if (extras.hit) {
    ++hits_;
    depth_ += extras.depth;
  }
  if (moving) {
    ++moving_;
    motion_[0] += extras.motion->x;
    motion_[1] += extras.motion->y;
    motionBack_[0] += extras.motionBack->x;
    motionBack_[1] += extras.motionBack->y;
  }
  // A silhouette: the pixel's samples see different objects moving differently.
  if (!extras.motionSampled) return;
  const int object = extras.hit ? extras.object : -1;
  if (firstObject_ == -2) {
    firstObject_ = object;
    firstMotion_ = extras.motion;
  } else if (object != firstObject_ && conflicting(firstMotion_, extras.motion)) {
    silhouette_ = true;
  }
}

void DecomposedFilm::Pixel::addReflectance(const SampleComponents& sample) {
  for (uint32_t bits = sample.touched; bits != 0; bits &= bits - 1) {
    const auto k = static_cast<size_t>(std::countr_zero(bits));
    if (!sample.hasFeatures(k) || !sample.features[k].reflectance.isFinite()) continue;
    Component& c = components_[k];
    ++c.reflectanceOnly;
    addTo(c.reflectance, sample.features[k].reflectance);
  }
}

void DecomposedFilm::Pixel::setSpecularMotion(int component, std::optional<Vec2f> forward,
                                              std::optional<Vec2f> backward) {
  Component& c = components_[static_cast<size_t>(component)];
  c.specular = true;
  c.specularMotion = forward;
  c.specularMotionBack = backward;
}

void DecomposedFilm::write(size_t p, const Pixel& sums) const {
  const double n = sums.samples_;
  for (size_t k = 0; k < components_.size(); ++k) {
    const ComponentChannels& out = components_[k];
    const Pixel::Component& c = sums.components_[k];
    const double features = std::max(1, c.features);
    const double reflectanceSamples = std::max(1, c.features + c.reflectanceOnly);
    const double moving = std::max(1, c.moving);
    for (int i = 0; i < 3; ++i) {
      const double mean = n > 0 ? c.color[i] / n : 0.0;
      const double variance = n > 1 ? std::max(0.0, c.colorSquared[i] - n * mean * mean) / ((n - 1) * n) : 0.0;
      const auto reflectance = static_cast<float>(c.reflectance[i] / reflectanceSamples);
      out.color[i][p] = static_cast<float>(mean);
      out.variance[i][p] = static_cast<float>(variance);
      out.reflectance[i][p] = reflectance;
      out.irradiance[i][p] = effectiveIrradiance(static_cast<float>(mean), reflectance);
      out.direct[i][p] = n > 0 ? static_cast<float>(c.direct[i] / n) : 0.0f;
    }
    const double length = std::sqrt(c.normal[0] * c.normal[0] + c.normal[1] * c.normal[1] + c.normal[2] * c.normal[2]);
    for (int i = 0; i < 3; ++i) out.normal[i][p] = length > 0 ? static_cast<float>(c.normal[i] / length) : 0.0f;
    out.objectId[p] = static_cast<float>(c.objectId);
    out.primitive[p] = static_cast<float>(c.primitive);
    for (int i = 0; i < 2; ++i) out.uv[i][p] = static_cast<float>(c.uv[i] / features);
    out.depth[p] = static_cast<float>(c.depth / features);
    out.coverage[p] = n > 0 ? static_cast<float>(c.features / n) : 0.0f;
    if (c.specular) {
      const bool valid = c.specularMotion && c.specularMotionBack;
      out.motion[0][p] = valid ? c.specularMotion->x : 0.0f;
      out.motion[1][p] = valid ? c.specularMotion->y : 0.0f;
      out.motionBack[0][p] = valid ? c.specularMotionBack->x : 0.0f;
      out.motionBack[1][p] = valid ? c.specularMotionBack->y : 0.0f;
      out.motionValid[p] = valid ? 1.0f : 0.0f;
      continue;
    }
    for (int i = 0; i < 2; ++i) {
      out.motion[i][p] = static_cast<float>(c.motion[i] / moving);
      out.motionBack[i][p] = static_cast<float>(c.motionBack[i] / moving);
    }
    out.motionValid[p] = c.moving > 0 ? 1.0f : 0.0f;
  }
  depth_[p] = sums.hits_ > 0 ? static_cast<float>(sums.depth_ / sums.hits_) : 0.0f;
  const double moving = std::max(1, sums.moving_);
  for (int i = 0; i < 2; ++i) {
    motion_[i][p] = static_cast<float>(sums.motion_[i] / moving);
    motionBack_[i][p] = static_cast<float>(sums.motionBack_[i] / moving);
  }
  silhouette_[p] = sums.silhouette_ ? 1.0f : 0.0f;
  movingCaustic_[p] = n > 0 ? static_cast<float>(sums.movingCaustic_ / n) : 0.0f;
}

}  // namespace pathfarm
