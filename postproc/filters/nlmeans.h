#pragma once
// Joint NL-means (Rousselle, Manzi and Zwicker 2013), with exactly the weights of Zimmer et
// al. 2015's supplementary material: a patch-wise color distance normalized by the
// per-pixel variances (with the variance-cancellation term and k_c), a bilateral weight
// per feature normalized by tau and the feature's gradient, w = min(w_c, min_f w_f), and
// exponential kernels. Frames of a spatio-temporal window must already be warped to the
// current frame; pixels marked invalid in a neighbour frame do not contribute.
//
// What is computed, for a pixel p of frames[0] and a pixel q at the same position plus an
// offset (dx, dy) in |dx|, |dy| <= r of any frame t of the window:
//
//   per color channel i (C channels), with u the color and V its variance:
//     d_i(p, q) = ((u_i(p) - u_i(q))^2 - alpha (V_i(p) + min(V_i(p), V_i(q))))
//                 / (eps + kc^2 (V_i(p) + V_i(q))),                       eps = 1e-10
//     d(p, q)   = (1/C) sum_i d_i(p, q)
//   patch distance: the mean of d(p + s, q + s) over the patch offsets s in [-f, f]^2 for
//     which p + s and q + s are both inside the image and both valid (a box filter of the
//     per-offset distance image, so the cost does not depend on f); w_c = exp(-max(0, D_c)).
//   Continuous feature g with C_g channels (variance W_g, zero when not given):
//     D_g = (1/C_g) sum_j ((g_j(p) - g_j(q))^2 - (W_j(p) + min(W_j(p), W_j(q))))
//           / (kf^2 max(tau, (1/C_g) sum_j W_j(p), (1/C_g) sum_j |grad g_j(p)|^2))
//     where grad is the central difference of frames[0]'s feature at p (edge-clamped
//     neighbours, so one-sided halves at the border); w_g = exp(-max(0, D_g)). Averaging
//     over channels instead of summing only rescales tau by C_g.
//   ExactMatch feature: w_g = 1 when every channel is equal at p and q, else 0.
//   w(p, q) = min(w_c, min_g w_g); the center pixel (frame 0, offset 0) has weight 1.
//   u_hat(p) = sum w(p, q) u(q) / sum w(p, q).
//
// Variance cancellation: the color term follows Rousselle, Knaus and Zwicker 2012
// ("Adaptive rendering with non-local means filtering"): alpha scales the subtracted
// variance Var(p) + Var(p, q), Var(p, q) = min(Var(p), Var(q)). The expected squared
// difference of two independent estimates of one value is Var(p) + Var(q), so with
// alpha = 1 the numerator is about 0 for equal means and variances, and alpha > 1 also
// accepts differences within a few standard deviations (smoother, more biased); the
// default is alpha = 4 with k_c = 0.45.
// The feature term always cancels with strength 1, as in Rousselle et al. 2013.
//
// Robustness: a pixel whose color or variance is not finite (or implausibly large:
// |color| > 1e15, variance > 1e30) is invalid: it never contributes, its per-pixel
// distances are left out of the patches around it, and as a center it is filtered from its
// valid neighbours alone (output 0 when none has any weight); NlMeansStats counts these.
// Pixels of frames[0] whose valid is 0 are treated the same way. A negative variance
// counts as 0; non-finite feature values count as 0.
//
// Numerics: e^-x is a polynomial of fixed precision (relative error < 1e-6, 0 beyond
// x = 87), and per-pixel distances are clamped at a bound so large that any patch
// holding a clamped pixel has weight 0 anyway. They are then rounded to a grid fine
// enough for a double to sum a row of them exactly (about 1e-6 with the defaults, for
// images up to 2^16 pixels wide), so that their patch sums are exact: a
// pixel's output depends only on the pixels within radius + patch of it and on where the
// image ends, not on where the image or a band of rows starts. So the output is the same
// bits for any thread count, and a window of rows cut out with that margin filters to the
// whole image's bits. The AVX2 build of the filter (NlMeansSettings::wideVectors) does the
// same float operations in the same order, without FMA: the same bits on any x86-64 CPU.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace pathfarm {

// A multi-channel float image: `channels` planes of width x height, row-major.
struct Planes {
  int width = 0, height = 0;
  std::vector<std::vector<float>> channels;

  Planes() = default;
  Planes(int w, int h, int count)
      : width(w), height(h), channels(static_cast<size_t>(count), std::vector<float>(static_cast<size_t>(w) * h)) {}
  size_t pixelCount() const { return static_cast<size_t>(width) * static_cast<size_t>(height); }
};

enum class FeatureKind {
  Continuous,  // normal, reflectance, depth: the bilateral weight
  ExactMatch,  // object id: weight 1 where equal, 0 elsewhere
};

struct NlMeansSettings {
  int radius = 5;      // r: search window (2r+1)^2 per frame
  int patch = 3;       // f: patches of side 2f+1
  float kc = 0.45f;    // color sensitivity
  float kf = 0.6f;     // feature sensitivity
  float tau = 0.001f;  // tau^2 of the paper: floor of the feature normalization
  float alpha = 4.0f;  // variance cancellation strength (Rousselle et al. 2012)
  // Only frame 0's valid pixels are wanted: the filter skips the rows and columns that hold
  // none, and invalid pixels come out 0 instead of filled from their neighbours. A sparse
  // frame (re-rendered pixels) then filters at the cost of what it holds.
  bool validCentersOnly = false;
  // AVX2 where the CPU has it: the same bits as without (nlmeans.cpp), faster. Off only
  // to compare the two.
  bool wideVectors = true;
};

// One frame to filter and its (warped) neighbours. Index 0 is the frame being filtered.
struct NlMeansFrame {
  Planes color;                         // what is filtered (e.g. effective irradiance), any channel count
  Planes variance;                      // per-pixel variance of the mean, same channels as color
  std::vector<Planes> features;         // per feature in NlMeansInput::features order
  std::vector<Planes> featureVariance;  // may be empty, or per feature (an entry may be empty)
  std::vector<float> valid;             // per pixel, 1 where this frame contributes (empty: all)
};

struct NlMeansInput {
  std::vector<NlMeansFrame> frames;       // frames[0] is filtered; others contribute
  std::vector<FeatureKind> featureKinds;  // one per feature
};

struct NlMeansStats {
  size_t invalidCenters = 0;           // invalid pixels of frames[0] (broken color or variance, or valid 0)
  size_t unfilledCenters = 0;          // of those, pixels no neighbour could fill (output 0)
  std::vector<uint8_t> invalidCenter;  // per pixel of frames[0]: 1 where it was invalid
};

// The filtered color of frames[0]. Throws std::invalid_argument for mismatched sizes or
// channel counts and for negative r or f.
Planes jointNlMeans(const NlMeansInput& input, const NlMeansSettings& settings, NlMeansStats* stats = nullptr);

// The same, filtering only the part of the frames that holds anything: the bounding box of
// the pixels where some frame's color or variance is not 0 (or not finite), or frames[0]
// is invalid, grown by 2 (radius + patch), so that every pixel whose value can be other
// than 0 sees its whole neighbourhood; everything else is 0, as jointNlMeans makes it.
// A component that lives on a few objects (a mirror's reflection, glass) is filtered at
// the cost of their area. The result is jointNlMeans's, bit for bit.
// With `wanted`, only the pixels of that rectangle matter to the caller: the filtered
// part shrinks to it, grown by radius + patch (the partners its pixels compare and their
// patches), and pixels outside it may come out otherwise than jointNlMeans makes them.
struct NlMeansArea {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // [x0, x1) x [y0, y1)
};
Planes jointNlMeansOnContent(const NlMeansInput& input, const NlMeansSettings& settings,
                             NlMeansStats* stats = nullptr, const NlMeansArea* wanted = nullptr);

// The terms of the weights between every pixel p of frames[0] and q = p + (dx, dy) in
// frames[frame], computed by the same code as jointNlMeans (for tests and diagnostics).
// Where q is outside the image the distances are +infinity and the weight is 0.
struct NlMeansPairTerms {
  std::vector<float> colorDistance;                 // the patch distance D_c (before max(0, .))
  std::vector<std::vector<float>> featureDistance;  // per feature: D_g; ExactMatch: 0 or +inf
  std::vector<float> weight;                        // w(p, q), 0 where q is invalid
};
NlMeansPairTerms jointNlMeansPairTerms(const NlMeansInput& input, const NlMeansSettings& settings, int frame, int dx,
                                       int dy);

}  // namespace pathfarm
