#pragma once
// Forward splatting with a depth test: every active source pixel p carries its values to
// p + d(p) and spreads them over the four nearest pixel centres with bilinear weights.
// Where several sources land on one pixel the nearest surface wins: the pixel's reference
// depth is the smallest depth among the contributions of footprint weight >=
// strongFootprint (0.25 by default; all of them when none is that strong), and only
// contributions with depth <=
// reference * (1 + depthTolerance) are kept; their weighted mean is the pixel's value.
// Depths <= 0 ("nothing there") count as infinitely far. A pixel whose kept weight is
// below minCoverage is not covered (a hole). Shared by frame interpolation and motion blur.
#include <cstdint>
#include <vector>

#include "postproc/filters/nlmeans.h"

namespace pathfarm {

struct SplatSource {
  const Planes* values = nullptr;            // the channels carried
  const std::vector<float>* depth = nullptr;  // null: every source at the same depth
  std::vector<float> dx, dy;                 // displacement of each source pixel
  std::vector<uint8_t> active;               // 1 where the pixel splats (empty: everywhere)
};

struct SplatSettings {
  float depthTolerance = 0.05f;  // relative: a surface this much farther still blends
  float minCoverage = 0.1f;      // kept footprint weight below this: a hole
  // Footprint weight a contribution needs to set the reference depth. 0: the nearest of
  // all contributions, however weak (motion blur composites the uncovered part of a
  // pixel over the background itself, so a weak foreground edge must not be averaged
  // with the background it partly covers).
  float strongFootprint = 0.25f;
};

struct SplatResult {
  Planes values;                 // normalized; 0 where not covered
  std::vector<float> weight;     // kept footprint weight
  std::vector<float> depth;      // weighted mean kept depth; +inf where not covered
  std::vector<uint8_t> covered;  // 1 where weight >= minCoverage
};

SplatResult forwardSplat(const SplatSource& source, const SplatSettings& settings);

// Fills the uncovered pixels of `result` from covered 4-neighbours, ring by ring, each
// taking the neighbour of largest depth (the background a moving surface uncovered).
// Pixels with no covered pixel anywhere stay as they are. Returns how many were filled.
size_t fillHolesFromBackground(SplatResult& result);

}  // namespace pathfarm
