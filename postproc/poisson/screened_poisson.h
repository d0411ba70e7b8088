#pragma once
// Screened Poisson reconstruction of a window of frames (Manzi et al. 2016, Section 5):
//   min_I  || alpha (I - I_g) ||_p^p + || H I - G ||_p^p
// with H the spatial, temporal and mixed difference operators (poisson_system.h), I_g
// the primal images and G the sampled differences, per color channel.
//   L2: conjugate gradients on the normal equations with a Jacobi preconditioner,
//       starting from the primal images. An iteration is three passes over memory: the
//       operator (which also returns p.Ap), r and the next r.z, then x and p.
//   L1: iteratively reweighted least squares: each round solves the L2 problem with row
//       weights 1 / max(|residual|, epsilon) from the previous round (kept as bfloat16,
//       within 2^-8), so a row weighs by its absolute rather than its squared error.
//       This is the standard IRLS majorizer of the L1 norm smoothed below epsilon (a
//       round solved exactly never raises the smoothed objective, up to the weights'
//       rounding), warm-started, with a few CG iterations per round. epsilon starts
//       large and goes down geometrically over the rounds (smoothing continuation): the
//       first rounds then see a well-conditioned system, and the same iterations reach
//       a lower L1 objective than a fixed small epsilon (docs/performance.md).
// Emitters seen directly from the camera are added back afterwards.
#include <array>
#include <string>
#include <vector>

#include "postproc/poisson/gradient_frame.h"

namespace pathfarm {

enum class PoissonNorm { L1, L2 };

PoissonNorm parsePoissonNorm(const std::string& text);  // "l1" or "l2"; throws std::invalid_argument

struct PoissonSettings {
  float alpha = 0.2f;
  PoissonNorm norm = PoissonNorm::L2;
  int maxIterations = 400;  // conjugate-gradient iterations (L2); the channels are solved side by side
  // Stop when |residual| <= tolerance * |right-hand side| (L2), or * the round's starting
  // |residual| (an L1 round).
  float tolerance = 1e-5f;
  int irlsRounds = 10;             // L1: the L2 solve, then reweighted rounds
  int irlsIterations = 14;         // CG iterations per L1 round
  float irlsStartEpsilon = 1e-1f;  // L1: epsilon of the first reweighted round
  float irlsEpsilon = 1e-3f;       // L1: of the last; residuals below epsilon weigh like epsilon
};

struct PoissonStats {
  int iterations = 0;           // CG iterations (all three channels at once), over all rounds
  double relativeResidual = 0;  // the last solve's, largest over channels
};

// The reconstruction of each frame of the window (without direct emission), per channel.
std::vector<GradientFrame::Color> reconstructWindow(const std::vector<const GradientFrame*>& frames,
                                                    const PoissonSettings& settings, PoissonStats* stats = nullptr);

}  // namespace pathfarm
