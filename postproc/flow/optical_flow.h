#pragma once
// Variational optical flow for motion estimation of path-space components (Zimmer et al.
// 2015, Sections 4.2/4.3 and supplementary 3), after Brox, Bruhn, Papenberg and Weickert
// 2004 ("High accuracy optical flow estimation based on a theory for warping").
//
// A flow field maps a pixel p of image A to p + flow(p) in image B (pixel centres at integer
// coordinates, like postproc/filters/warp.h and the renderer's motion.X/Y), i.e. A(p) ~
// B(p + flow(p)).
//
// Energy, for the flow w = (u, v) and C channels (images are first optionally taken to the
// log domain, log(max(v, 1e-4)), then presmoothed with a Gaussian):
//
//   E(w) = sum_p  m(p) [ Psi(D_b(p)) + gamma Psi(D_g(p)) ]  +  lambda Psi(|grad u|^2 + |grad v|^2)
//
//   D_b = (1/C) sum_c theta_c (B_c(p + w) - A_c(p))^2,   theta_c = 1 / (|grad I_c|^2 + zeta^2)
//   D_g = (1/C) sum_c [ theta_xc (B_xc(p + w) - A_xc(p))^2 + theta_yc (B_yc(p + w) - A_yc(p))^2 ],
//         theta_xc = 1 / (|grad I_xc|^2 + zeta^2), theta_yc = 1 / (|grad I_yc|^2 + zeta^2)
//   (linearized about the current flow; grad I is the mean of A's and the warped B's gradient,
//   I_x, I_y the first derivatives)
//   Psi(s^2) = sqrt(s^2 + epsilon^2), epsilon = 0.001
//
// The normalization ("normalized data term", Zimmer et al. 2011) turns the linearized
// brightness-constancy residual into the distance (in pixels) of the flow from the constraint
// line, so lambda weighs pixels against pixels and does not depend on the image's scale or
// contrast (zeta only damps it in flat regions: zeta is in the images' units — after the log
// for logDomain — and should be well below the gradients of the structures to be matched).
// Averaging over channels keeps lambda's meaning independent of the channel count.
// m(p) is 0 at pixels of the occlusion mask and where p + w leaves B; there the flow comes
// from the smoothness term alone.
//
// Minimization: coarse-to-fine pyramid (factor `downsample`), at every level `warps`
// re-linearizations about the current flow (B and its derivatives warped to A by bilinear
// lookup), each solved for the increment (du, dv) by `fixedPointIterations` lagged-
// nonlinearity steps (Psi' frozen) of `sorIterations` red-black SOR sweeps. Derivatives are
// 5-point central differences; the spatial derivatives of the data term average A's and the
// warped B's.
//
// Determinism: every step is either pointwise or a red-black sweep whose pixels of one colour
// depend only on the other colour, parallelized over rows with TBB; no reductions. Results
// are bit-identical for any thread count.
//
// Bad input (empty or mismatched sizes, differing channel counts, non-finite pixels, flows or
// mask values, settings out of range) throws std::invalid_argument with a message saying
// what is wrong. Non-finite pixels are rejected rather than masked: mask them out yourself
// (replace the value and set the occlusion mask) if that is what you want.
#include <cstddef>
#include <vector>

#include "postproc/filters/nlmeans.h"

namespace pathfarm {

// Two planes in pixels: pixel p of image A maps to p + (dx[p], dy[p]) in image B.
struct FlowField {
  int width = 0, height = 0;
  std::vector<float> dx, dy;

  FlowField() = default;
  FlowField(int w, int h, float x = 0.0f, float y = 0.0f)
      : width(w),
        height(h),
        dx(static_cast<size_t>(w) * static_cast<size_t>(h), x),
        dy(static_cast<size_t>(w) * static_cast<size_t>(h), y) {}
  size_t pixelCount() const { return static_cast<size_t>(width) * static_cast<size_t>(height); }
};

struct FlowSettings {
  float lambda = 0.75f;          // smoothness weight (the paper: 0.75; 0.25 for caustic-carrying components)
  float gradientWeight = 0.0f;   // gamma: weight of gradient constancy (0 = brightness constancy only)
  float downsample = 0.75f;      // pyramid factor, in [0.5, 0.9]
  int minLevelSize = 16;         // coarsest level: its smaller side is at least this (or the image's)
  int maxLevels = 0;             // pyramid levels at most, the finest included (0: down to minLevelSize)
  int warps = 2;                 // re-linearizations (warps) per pyramid level
  int fixedPointIterations = 3;  // lagged-nonlinearity steps per warp
  int sorIterations = 10;        // red-black SOR sweeps per fixed-point step
  float sorOmega = 1.8f;         // over-relaxation, in (0, 2)
  float epsilon = 0.001f;        // Psi(s^2) = sqrt(s^2 + epsilon^2)
  float zeta = 0.01f;            // normalization floor: theta = 1 / (|grad|^2 + zeta^2)
  float presmoothing = 0.5f;     // sigma (pixels) of the Gaussian applied to both images (0: none)
  bool logDomain = false;        // match log(max(v, 1e-4)) (for irradiance)
};

// The flow from `a` to `b` (same size and channel count, >= 1 channel). `occlusionMask` (may
// be null or empty; else one value per pixel of `a`) disables the data term where it is
// nonzero (values in [0, 1] are used as the fraction to disable).
FlowField computeFlow(const Planes& a, const Planes& b, const FlowSettings& settings,
                      const std::vector<float>* occlusionMask = nullptr);

// Where the images of a bootstrapped flow lie in their frames: A is rows [top, top + its
// height) of a frame `frameHeight` rows tall (0: A is the frame), B holds rows
// [neighbourTop, neighbourTop + its height) of the other frame, the same size.
struct FlowRows {
  int top = 0, frameHeight = 0, neighbourTop = 0;
};

// Bootstrapping (Zimmer et al. 2015, Section 4.3): B is warped to A along `primaryMotion`
// (B(p + primary(p)), bilinear, postproc/filters/warp.h), the residual flow r from A to the
// warped B is computed (data term off where p + primary(p) leaves B, and at `occlusionMask`),
// and the result is r(p) + primary(p + r(p)) (primary looked up bilinearly, clamped to A's
// rows), so that A(p) ~ B(p + result(p)). Where p + primary(p) leaves B's frame the warped
// B takes A's own value: the presmoothing and derivatives then see no edge A lacks, and
// the result does not depend on which rows of B are held. So for a band of rows (`rows`)
// B need hold only the rows warpSourceRows names for the primary motion placed there (no
// rows at all when no source lies inside B's frame); rows of B outside its frame, or
// missing some of those, are refused (std::invalid_argument).
FlowField bootstrappedFlow(const Planes& a, const Planes& b, const FlowField& primaryMotion,
                           const FlowSettings& settings, const std::vector<float>* occlusionMask = nullptr,
                           FlowRows rows = {});

struct OcclusionResult {
  int width = 0, height = 0;
  std::vector<float> mask;  // 1 where occluded, else 0
  size_t count = 0;         // pixels with mask 1
};

// Forward-backward consistency: p is occluded when p + forward(p) lies outside B's pixel
// footprints ([-0.5, w - 0.5) x [-0.5, h - 0.5)) or |forward(p) + backward(p + forward(p))| >
// threshold pixels (backward looked up bilinearly). `backward` maps B to A. Throws
// std::invalid_argument for mismatched sizes, non-finite flows or a negative threshold.
OcclusionResult forwardBackward(const FlowField& forward, const FlowField& backward, float threshold = 0.1f);

// Flow with occlusion handling: forward (A -> B) and backward (B -> A) flows are computed,
// their forward-backward check gives the occlusion mask of A, and the forward flow is
// recomputed with the data term disabled at occluded pixels (they take their flow from the
// smoothness term). Returns that flow; the mask is stored in `occlusion` when non-null. The
// solver's flows are accurate to a few hundredths of a pixel in textured regions but less at
// motion boundaries, so the default threshold here is 0.5 px rather than 0.1.
FlowField flowWithOcclusions(const Planes& a, const Planes& b, const FlowSettings& settings,
                             OcclusionResult* occlusion = nullptr, float threshold = 0.5f);

}  // namespace pathfarm
