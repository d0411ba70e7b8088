#include "scheduler/shot_verdict.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace pathfarm::farm {
namespace {

std::string numberText(const char* pattern, double value) {
  if (std::isinf(value)) return value > 0 ? "infinity" : "-infinity";
  char text[64];
  std::snprintf(text, sizeof text, pattern, value);
  return text;
}

double figureOr(const std::map<std::string, double>& figures, const std::string& name, double otherwise) {
  const auto found = figures.find(name);
  return found == figures.end() ? otherwise : found->second;
}

// What the errors rest on, for the verdict's parenthesis.
std::string errorFigures(const ShotReport& report, const Interval& final, const Interval& baseline, double noise) {
  return " (relative cost " + numberText("%.2f", report.relative_cost()) + " at an error against the truth of " +
         intervalText(final, "%.4f") + ", pt's " + intervalText(baseline, "%.4f") + " at the same spp" +
         (noise > 0 ? ", the reference's noise " + numberText("%.4f", noise) + " taken out" : "") + ")";
}

// The reference spp whose noise would be a tenth of `error`, from the noise at
// `referenceSpp` (noise falls as 1/spp), rounded up to a power of two.
int resolvingSpp(int referenceSpp, double noise, double error) {
  const double needed = referenceSpp * 10 * noise / error;
  double spp = 1;
  while (spp < needed && spp < (1 << 24)) spp *= 2;
  return static_cast<int>(spp);
}

// The warnings that follow the verdict: artifacts, an error the reference cannot resolve,
// flicker; each only where the intervals show it.
std::string warnings(const std::map<std::string, double>& figures, const Interval& final, double noise,
                     int referenceSpp) {
  std::string text;
  const auto tile = intervalFigure(figures, "worst_tile_truth", ".final");
  const auto ptTile = intervalFigure(figures, "worst_tile_truth", ".baseline");
  if (tile && ptTile && ptTile->estimate() > 0 && tile->low() > 2 * ptTile->high())
    text += " Its worst 16x16 tile has " + numberText("%.1f", tile->estimate() / ptTile->estimate()) +
            "x pt's error: look for artifacts.";
  if (!(final.low() > 0)) {
    text += " Its error cannot be told from 0 at this reference (its noise " + numberText("%.4f", noise) +
            "): only the interval's high end bounds the cost at equal error; raise reference_spp to measure it.";
  } else if (noise > final.estimate() / 10) {
    text += " The reference resolves its error only coarsely: the reference's noise " + numberText("%.4f", noise) +
            " is more than a tenth of it; a reference of " +
            std::to_string(resolvingSpp(referenceSpp, noise, final.estimate())) + " spp would resolve it.";
  }
  if (const auto temporal = intervalFigure(figures, "temporal_truth", ".final")) {
    const auto ptTemporal = intervalFigure(figures, "temporal_truth", ".baseline");
    if (ptTemporal && temporal->low() > ptTemporal->high())
      text += " It flickers more than pt (temporal error " + intervalText(*temporal, "%.4f") + " against " +
              intervalText(*ptTemporal, "%.4f") + ").";
  }
  return text;
}

}  // namespace

std::optional<Interval> intervalFigure(const std::map<std::string, double>& figures, const std::string& name,
                                       const std::string& suffix) {
  const auto estimate = figures.find(name + suffix);
  if (estimate == figures.end()) return std::nullopt;
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  Interval interval;
  interval.set_estimate(estimate->second);
  interval.set_low(figureOr(figures, name + "_low" + suffix, -kInfinity));
  interval.set_high(figureOr(figures, name + "_high" + suffix, kInfinity));
  return interval;
}

std::string intervalText(const Interval& interval, const char* pattern) {
  return numberText(pattern, interval.estimate()) + " (" + numberText(pattern, interval.low()) + " to " +
         numberText(pattern, interval.high()) + ")";
}

void judge(ShotReport& report, Pipeline pipeline, const std::map<std::string, double>& figures) {
  report.set_cost_at_equal_error(-1);
  const auto ratio = intervalFigure(figures, "error_ratio");
  const auto final = intervalFigure(figures, "truth", ".final");
  const auto baseline = intervalFigure(figures, "truth", ".baseline");
  if (pipeline == PIPELINE_PT || !(report.relative_cost() > 0) || !final || !baseline) return;
  const double noise = figureOr(figures, "reference_noise", 0);
  const std::string& name = report.pipeline();
  // Without pt's error told apart from 0 there is no ratio to scale the cost by (the
  // evaluation leaves an unbounded one out).
  if (!ratio || !(baseline->low() > 0)) {
    report.set_verdict("The errors cannot be told from the reference's own noise (" + numberText("%.4f", noise) +
                       "): " + name + "'s error against the truth " + intervalText(*final, "%.4f") + ", plain pt's " +
                       intervalText(*baseline, "%.4f") + ". Raise reference_spp to compare them.");
    return;
  }
  const double cost = report.relative_cost();
  Interval* interval = report.mutable_cost_at_equal_error_interval();
  // An error against the truth is not below 0; an estimate that is (within the
  // reference's noise of 0) reads as 0.
  interval->set_estimate(std::max(0.0, cost * ratio->estimate()));
  interval->set_low(std::max(0.0, cost * ratio->low()));
  interval->set_high(cost * ratio->high());
  report.set_cost_at_equal_error(interval->estimate());
  const std::string figuresText = errorFigures(report, *final, *baseline, noise);
  std::string verdict;
  if (interval->high() < 1) {
    verdict = name + " paid off: " + intervalText(*interval, "%.2f") +
              " of plain pt's core-seconds for the same error, 95 % interval in parentheses" + figuresText + ".";
  } else if (interval->low() > 1) {
    verdict = name + " did not pay off: it cost " + intervalText(*interval, "%.2f") +
              "x what plain pt would for the same error, 95 % interval in parentheses" + figuresText +
              "; plain pt is the cheaper choice here.";
  } else {
    verdict = "Cannot tell at this reference whether " + name + " paid off: its cost at equal error is " +
              intervalText(*interval, "%.2f") + " of plain pt's, and that 95 % interval includes 1" + figuresText +
              ". Raise reference_spp to tell.";
  }
  report.set_verdict(verdict + warnings(figures, *final, noise, report.reference_spp()));
}

}  // namespace pathfarm::farm
