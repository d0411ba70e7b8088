#pragma once
// Arbitrary-length sequences as overlapping windows of frames (Manzi et al. 2016,
// Section 5.2): each window is reconstructed on its own, and a frame that several
// windows cover is their average weighted by a Hann window over each window's frames,
// so the result fades from one window into the next without a seam.
#include <cstddef>
#include <functional>
#include <vector>

#include "postproc/poisson/screened_poisson.h"

namespace pathfarm {

struct PoissonWindow {
  size_t first = 0, count = 0;  // frames [first, first + count) of the sequence
};

// Windows of `window` frames, each starting `window - overlap` after the previous, the
// last one moved back to end with the sequence (so it may overlap more); one shorter
// window when the sequence is shorter. Throws std::invalid_argument unless
// 0 <= overlap < window.
std::vector<PoissonWindow> planWindows(size_t frames, size_t window, size_t overlap);

// The blending weight of the index-th of `count` frames of a window: sin^2 of the
// position, > 0 everywhere so a frame at a sequence end keeps its only window.
float hannWeight(size_t index, size_t count);

// A frame's blend over the windows that cover it, added in window order: the farm and
// reconstructSequence blend with this, so their frames are the same bits.
struct WindowBlend {
  GradientFrame::Color sum;
  float weight = 0;

  // The frame's reconstruction in a window where it is the index-th of `count` frames.
  void add(const GradientFrame::Color& solved, size_t index, size_t count);
  // The weighted mean plus the frame's direct emission.
  GradientFrame::Color finish(const GradientFrame::Color& directEmission) &&;
};

// The finished frame `index` of the sequence: reconstruction plus direct emission.
using FrameSink = std::function<void(size_t index, const GradientFrame::Color& color)>;
using FrameLoader = std::function<GradientFrame(size_t index)>;

// Reconstructs `frames` frames window by window, loading each frame when a window needs
// it and handing every frame to `sink` as soon as the last window covering it is done.
void reconstructSequence(size_t frames, const FrameLoader& load, const FrameSink& sink, size_t window, size_t overlap,
                         const PoissonSettings& settings, PoissonStats* stats = nullptr);

}  // namespace pathfarm
