#pragma once
// A benchmark's error figure against the truth: the frames' relMSE with the reference's
// own noise taken out pixel by pixel, with its 95 % interval (error_terms.h,
// error_interval.h), as a table cell. Where the reference's noise is more than a tenth of
// the figure, the reference cannot resolve it, and the cell gives only the interval's upper
// end as a bound ("≤ 0.0420"), which holds whatever the reference's noise.
#include <cstdio>
#include <string>
#include <vector>

#include "image/frame_image.h"
#include "postproc/metrics/error_interval.h"
#include "postproc/metrics/relmse.h"

namespace pathfarm::bench {

struct TruthFigure {
  Interval error;
  double referenceNoise = 0;  // the references' mean expected relMSE, from their variance

  bool resolved() const { return referenceNoise <= error.estimate / 10; }
  std::string text() const {
    char cell[96];
    if (resolved())
      std::snprintf(cell, sizeof cell, "%.4f (%.4f to %.4f)", error.estimate, error.low, error.high);
    else
      std::snprintf(cell, sizeof cell, "≤ %.4f", error.high);
    return cell;
  }
};

// Frames and their references in the same order; each reference carries its variance
// channels (variance.R, .G, .B: a path-traced render's).
inline TruthFigure truthFigureOf(const std::vector<FrameImage>& frames, const std::vector<FrameImage>& references) {
  TruthFigure figure;
  BlockedTerms terms;
  for (size_t f = 0; f < frames.size(); ++f) {
    terms.append(errorTerms(&frames[f], references.at(f)));
    figure.referenceNoise += expectedRelMse(references[f]) / static_cast<double>(frames.size());
  }
  figure.error = meanInterval(terms);
  return figure;
}

}  // namespace pathfarm::bench
