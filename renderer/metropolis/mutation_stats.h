#pragma once
// How often each kind of mutation was proposed and accepted, over one chain, a block of
// chains or a whole window; written into each frame's EXR attributes.
#include <cstdint>
#include <string>
#include <vector>

#include "image/frame_image.h"

namespace pathfarm {

struct MutationStats {
  std::vector<std::string> kinds;
  std::vector<uint64_t> proposed, accepted;
  int temporalKind = -1;        // index of the temporal mutation among kinds; -1 if none
  double finalDeltaSum = 0;     // the chains' tuned reaches D, summed, and their count
  uint64_t chains = 0;
  // No wall time: these counts travel in chunks and frames, whose bits must not depend on
  // the worker that made them.

  // Counts of zero for every kind of `kindNames`.
  static MutationStats forKinds(std::vector<std::string> kindNames, int temporal);

  uint64_t mutations() const;
  // Accepted over proposed; 0 when none was proposed.
  double acceptance(int kind) const;
  double temporalAcceptance() const { return temporalKind < 0 ? 0 : acceptance(temporalKind); }
  double meanFinalDelta() const { return chains > 0 ? finalDeltaSum / static_cast<double>(chains) : 0; }

  // Adds another chain's or block's counts (the same kinds).
  void add(const MutationStats& other);
  // "pathfarm.mlt.*" attributes: mutations, acceptance per kind, temporal acceptance, D.
  void writeAttributes(FrameImage& image) const;
  // Text with the exact counts and sums, for shipping a block's statistics between farm
  // tasks; parse throws std::invalid_argument naming what is wrong.
  std::string serialize() const;
  static MutationStats parse(const std::string& text);
  // One line for a progress report.
  std::string summary() const;
};

}  // namespace pathfarm
