#pragma once
// How much of a surface is there (glTF alphaMode MASK and BLEND): an alpha per texel (the
// base colour texture's alpha) times a factor. MASK keeps the points whose alpha reaches
// the cutoff; BLEND is rendered as stochastic transparency, each ray passing through with
// probability 1 - alpha (a cut-out whose average over samples is the blend; refraction
// and tinting by the blended colour are not modelled).
#include <cstdint>
#include <vector>

#include "renderer/math/vecmath.h"

namespace pathfarm {

class AlphaCoverage {
 public:
  enum class Mode { Mask, Blend };

  // `alpha`: width x height values, rows top (v = 1) to bottom; empty for `factor` alone.
  AlphaCoverage(Mode mode, float cutoff, float factor, int width, int height, std::vector<float> alpha);

  float alphaAt(Vec2f uv) const;
  // Whether a ray meeting the surface at `uv` stops there; `random` in [0, 1) decides
  // BLEND's stochastic pass-through.
  bool covers(Vec2f uv, float random) const;
  Mode mode() const { return mode_; }

 private:
  Mode mode_;
  float cutoff_, factor_;
  int width_, height_;
  std::vector<float> alpha_;
};

// A uniform number in [0, 1) from the bits of a hit, so a BLEND decision is the same for
// the same ray on every worker and thread count.
float hashToUnit(uint32_t a, uint32_t b, uint32_t c, uint32_t d);

}  // namespace pathfarm
