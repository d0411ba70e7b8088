#include "postproc/interpolation/irradiance_flow.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "image/row_bands.h"
#include "postproc/filters/decomposed_frame.h"
#include "postproc/interpolation/interpolation_input.h"

namespace pathfarm {
namespace {

bool holdsNothing(const Planes& planes) {
  for (const auto& plane : planes.channels)
    if (std::any_of(plane.begin(), plane.end(), [](float v) { return v != 0.0f; })) return false;
  return true;
}

// A field of rows [first, end) of a frame `frameHeight` rows tall, zero and invalid.
MotionField invalidRows(int width, int first, int end, int frameHeight) {
  const size_t pixels = static_cast<size_t>(width) * static_cast<size_t>(end - first);
  MotionField field{width, end - first, std::vector<float>(pixels, 0.0f), std::vector<float>(pixels, 0.0f),
                    std::vector<float>(pixels, 0.0f)};
  field.top = first;
  field.frameHeight = frameHeight;
  return field;
}

// Rows [first, end) of `planes`, which hold rows [top, top + height) of the frame.
Planes rowsOfPlanes(const Planes& planes, int top, int first, int end) {
  const size_t W = static_cast<size_t>(planes.width);
  Planes rows(planes.width, end - first, 0);
  for (const auto& plane : planes.channels)
    rows.channels.emplace_back(plane.begin() + static_cast<ptrdiff_t>((first - top) * W),
                               plane.begin() + static_cast<ptrdiff_t>((end - top) * W));
  return rows;
}

// Rows [first, end) of a keyframe's irradiance: those of its band's halo that `held`
// holds (from row `top`), and the rest read.
Planes irradianceRows(const ComponentRows& keyframe, const Planes& held, int top, int first, int end) {
  const int heldEnd = top + held.height;
  const int aboveEnd = std::min(end, top), heldFirst = std::max(first, top), heldLast = std::min(end, heldEnd),
            belowFirst = std::max(first, heldEnd);
  std::vector<Planes> parts;
  if (first < aboveEnd) parts.push_back(keyframe.irradiance(first, aboveEnd));
  if (heldFirst < heldLast) parts.push_back(rowsOfPlanes(held, top, heldFirst, heldLast));
  if (belowFirst < end) parts.push_back(keyframe.irradiance(belowFirst, end));
  if (parts.size() == 1) return std::move(parts.front());
  Planes rows(held.width, 0, 0);
  rows.channels.resize(held.channels.size());
  for (const Planes& part : parts) {
    rows.height += part.height;
    for (size_t c = 0; c < rows.channels.size(); ++c)
      rows.channels[c].insert(rows.channels[c].end(), part.channels[c].begin(), part.channels[c].end());
  }
  return rows;
}

// The flow of one band from the keyframe `from` to `to`, over the band's halo.
FlowField solveBand(const FlowBand& band, const ComponentBand& from, const ComponentBand& to,
                    const ComponentRows& toRows, const FlowSettings& settings) {
  const int width = toRows.width, frameHeight = toRows.height;
  const MotionField& primary = from.motion;
  checkField(primary, width, band.haloEnd - band.haloFirst, "the primary motion");
  // The initial guess: the primary motion, 0 where it is invalid.
  FlowField guess(width, primary.height);
  for (size_t p = 0; p < guess.pixelCount(); ++p)
    if (primary.valid.empty() || primary.valid[p] >= 0.5f) {
      guess.dx[p] = primary.x[p];
      guess.dy[p] = primary.y[p];
    }
  MotionField placed{width, guess.height, guess.dx, guess.dy, {}};
  placed.top = band.haloFirst;
  placed.frameHeight = frameHeight;
  const auto [sourceFirst, sourceEnd] = warpSourceRows(placed);
  const Planes target = sourceFirst < sourceEnd
                            ? irradianceRows(toRows, to.irradiance, band.haloFirst, sourceFirst, sourceEnd)
                            : Planes(width, 0, static_cast<int>(from.irradiance.channels.size()));
  return bootstrappedFlow(from.irradiance, target, guess, settings, nullptr,
                          {band.haloFirst, frameHeight, sourceFirst});
}

// Writes the band's rows of `flow` (over its halo) into the rows of `out` it keeps, valid
// where p + flow(p) lies inside the frame and `inconsistent` (empty: nowhere) is 0.
void keepBandRows(const FlowBand& band, const FlowField& flow, const std::vector<float>& inconsistent,
                  int frameHeight, MotionField& out) {
  const int width = flow.width;
  const int keptFirst = std::max(band.first, out.top), keptEnd = std::min(band.end, out.top + out.height);
  const size_t W = static_cast<size_t>(width);
  for (int y = keptFirst; y < keptEnd; ++y)
    for (int x = 0; x < width; ++x) {
      const size_t p = static_cast<size_t>(y - band.haloFirst) * W + static_cast<size_t>(x);
      const size_t q = static_cast<size_t>(y - out.top) * W + static_cast<size_t>(x);
      out.x[q] = flow.dx[p];
      out.y[q] = flow.dy[p];
      const float tx = static_cast<float>(x) + flow.dx[p], ty = static_cast<float>(y) + flow.dy[p];
      const bool inside = std::isfinite(tx) && std::isfinite(ty) && tx > -0.5f &&
                          tx < static_cast<float>(width) - 0.5f && ty > -0.5f &&
                          ty < static_cast<float>(frameHeight) - 0.5f;
      out.valid[q] = inside && (inconsistent.empty() || inconsistent[p] == 0.0f) ? 1.0f : 0.0f;
    }
}

// Rows [first, end) of a whole-frame field, placed in the frame.
MotionField rowsOfField(const MotionField& field, int first, int end) {
  const size_t W = static_cast<size_t>(field.width);
  const auto slice = [&](const std::vector<float>& plane) {
    if (plane.empty()) return plane;
    return std::vector<float>(plane.begin() + static_cast<ptrdiff_t>(first * W),
                              plane.begin() + static_cast<ptrdiff_t>(end * W));
  };
  MotionField rows{field.width, end - first, slice(field.x), slice(field.y), slice(field.valid)};
  rows.top = first;
  rows.frameHeight = field.height;
  return rows;
}

}  // namespace

std::vector<FlowBand> flowBandsOf(int frameHeight, FlowBanding banding) {
  if (frameHeight <= 0) throw std::invalid_argument("flow bands: the frame has no rows");
  if (banding.rows < 0 || banding.rows == 1 || banding.halo < 0)
    throw std::invalid_argument("flow bands: a band keeps 0 (the frame) or at least 2 rows, and no halo is negative");
  std::vector<FlowBand> bands;
  for (const auto& [first, end] : evenRowBands(frameHeight, banding.rows))
    bands.push_back({first, end, std::max(0, first - banding.halo), std::min(frameHeight, end + banding.halo)});
  return bands;
}

IrradianceFlows irradianceFlowRows(const ComponentRows& k0, const ComponentRows& k1, int first, int end,
                                   const FlowSettings& settings, FlowBanding banding, float consistency) {
  const int width = k0.width, height = k0.height;
  if (width <= 0 || height <= 0) throw std::invalid_argument("irradiance flow: keyframe 0 is empty");
  if (k1.width != width || k1.height != height)
    throw std::invalid_argument("irradiance flow: keyframe 1 is " + std::to_string(k1.width) + "x" +
                                std::to_string(k1.height) + ", keyframe 0 " + std::to_string(width) + "x" +
                                std::to_string(height));
  if (first < 0 || end > height || first >= end)
    throw std::invalid_argument("irradiance flow: rows " + std::to_string(first) + " to " + std::to_string(end) +
                                " are not rows of a frame " + std::to_string(height) + " rows tall");
  if (!(consistency >= 0.0f) || !std::isfinite(consistency))
    throw std::invalid_argument("irradiance flow: the consistency threshold must be finite and >= 0");
  FlowSettings logSettings = settings;
  logSettings.logDomain = true;
  IrradianceFlows flows{invalidRows(width, first, end, height), invalidRows(width, first, end, height)};
  for (const FlowBand& band : flowBandsOf(height, banding)) {
    if (band.end <= first || band.first >= end) continue;
    ++flows.bands;
    const ComponentBand b0 = k0.rows(band.haloFirst, band.haloEnd), b1 = k1.rows(band.haloFirst, band.haloEnd);
    if (holdsNothing(b0.irradiance) && holdsNothing(b1.irradiance)) {
      ++flows.bandsSkipped;
      flows.skippedRows += std::min(end, band.end) - std::max(first, band.first);
      continue;
    }
    const FlowField forward = solveBand(band, b0, b1, k1, logSettings);
    const FlowField backward = solveBand(band, b1, b0, k0, logSettings);
    // Both directions are solved on the same halo, so each is checked against the other
    // there; a flow leading beyond the halo counts as inconsistent.
    const auto inconsistent = [&](const FlowField& there, const FlowField& back) {
      return consistency > 0.0f ? forwardBackward(there, back, consistency).mask : std::vector<float>{};
    };
    keepBandRows(band, forward, inconsistent(forward, backward), height, flows.forward);
    keepBandRows(band, backward, inconsistent(backward, forward), height, flows.backward);
  }
  return flows;
}

void addIrradianceFlow(ComponentMotions& motions, const FrameImage& k0, const FrameImage& k1,
                       const FlowSettings& settings, FlowBanding banding, float consistency) {
  const int width = k0.width(), height = k0.height();
  if (width <= 0 || height <= 0) throw std::invalid_argument("irradiance flow: keyframe 0 is empty");
  checkSameLayout(k0, k1, "keyframe 0", "keyframe 1");
  const std::vector<std::string> components = decompositionComponents(k0);
  std::vector<std::pair<const std::string, ComponentMotion>*> flowing;
  for (auto& entry : motions.components) {
    if (entry.first.empty()) continue;
    if (std::find(components.begin(), components.end(), entry.first) == components.end())
      throw std::invalid_argument("irradiance flow: the keyframes have no component \"" + entry.first + "\"");
    flowing.push_back(&entry);
  }
  tbb::parallel_for(size_t(0), flowing.size(), [&](size_t i) {
    const std::string& c = flowing[i]->first;
    ComponentMotion& motion = flowing[i]->second;
    const std::string what = "irradiance flow: component \"" + c + "\"";
    checkField(motion.forward, width, height, what + " forward motion");
    checkField(motion.backward, width, height, what + " backward motion");
    const auto rowsOf = [&](const FrameImage& frame, const MotionField& towards, const std::string& label) {
      ComponentRows rows{width, height, {}, {}};
      rows.irradiance = [&frame, &c, label, width](int first, int end) {
        Planes planes(width, end - first, 0);
        for (const char* rgb : {"R", "G", "B"}) {
          const std::vector<float>& channel = finiteChannel(frame, c + ".irradiance." + rgb, label);
          const size_t W = static_cast<size_t>(width);
          planes.channels.emplace_back(channel.begin() + static_cast<ptrdiff_t>(first * W),
                                       channel.begin() + static_cast<ptrdiff_t>(end * W));
        }
        return planes;
      };
      rows.rows = [irradiance = rows.irradiance, &towards](int first, int end) {
        return ComponentBand{irradiance(first, end), rowsOfField(towards, first, end)};
      };
      return rows;
    };
    const IrradianceFlows flows = irradianceFlowRows(rowsOf(k0, motion.forward, "keyframe 0"),
                                                     rowsOf(k1, motion.backward, "keyframe 1"), 0, height, settings,
                                                     banding, consistency);
    motion.irradianceForward = flows.forward;
    motion.irradianceBackward = flows.backward;
    motion.irradianceForward.top = motion.irradianceBackward.top = 0;
    motion.irradianceForward.frameHeight = motion.irradianceBackward.frameHeight = 0;
    motion.hasIrradianceMotion = true;
  });
}

}  // namespace pathfarm
