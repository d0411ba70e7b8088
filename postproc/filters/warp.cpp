#include "postproc/filters/warp.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace pathfarm {
namespace {

void checkField(const MotionField& motion) {
  const size_t pixels =
      static_cast<size_t>(std::max(0, motion.width)) * static_cast<size_t>(std::max(0, motion.height));
  if (motion.width <= 0 || motion.height <= 0 || motion.x.size() != pixels || motion.y.size() != pixels ||
      (!motion.valid.empty() && motion.valid.size() != pixels))
    throw std::invalid_argument("warp: the motion field's planes do not match its " + std::to_string(motion.width) +
                                "x" + std::to_string(motion.height) + " pixels");
  // Where a window's rows lie is the caller's arithmetic, not the frame's content.
  if (motion.top < 0 || (motion.frameHeight > 0 ? motion.top + motion.height > motion.frameHeight : motion.top != 0))
    throw std::logic_error("warp: rows " + std::to_string(motion.top) + " to " +
                           std::to_string(motion.top + motion.height) + " are not rows of a frame " +
                           std::to_string(motion.frameHeight) + " rows tall");
}

// Where pixel (px, py) looks up, and whether that is a valid source.
struct Source {
  float x, y;
  bool inside;
};

// Pixel (px, py) of the field, py its row in the field; the source's y is in frame rows.
Source sourceOf(const MotionField& motion, size_t p, int px, int py) {
  const float mx = motion.x[p], my = motion.y[p];
  const float frameY = static_cast<float>(motion.top + py);
  if (!std::isfinite(mx) || !std::isfinite(my)) return {static_cast<float>(px), frameY, false};
  const float sx = static_cast<float>(px) + mx, sy = frameY + my;
  const bool inside = sx >= -0.5f && sx < static_cast<float>(motion.width) - 0.5f && sy >= -0.5f &&
                      sy < static_cast<float>(motion.rowsOfFrame()) - 0.5f;
  return {sx, sy, inside};
}

bool motionHolds(const MotionField& motion, size_t p) {
  return motion.valid.empty() || (motion.valid[p] != 0.0f && !std::isnan(motion.valid[p]));
}

}  // namespace

MotionField motionTowards(const FrameImage& current, NeighbourFrame neighbour, const std::string& prefix,
                          const std::string& label) {
  const std::string base = prefix + (neighbour == NeighbourFrame::Previous ? "motion_back" : "motion");
  MotionField motion;
  motion.width = current.width();
  motion.height = current.height();
  motion.x = requireChannel(current, base + ".X", label);
  motion.y = requireChannel(current, base + ".Y", label);
  if (current.hasChannel(prefix + "motion_valid.Y")) motion.valid = current.channel(prefix + "motion_valid.Y");
  return motion;
}

std::vector<float> warpValidity(const MotionField& motion) {
  checkField(motion);
  std::vector<float> valid(motion.x.size(), 0.0f);
  for (int y = 0; y < motion.height; ++y) {
    for (int x = 0; x < motion.width; ++x) {
      const size_t p = static_cast<size_t>(y) * static_cast<size_t>(motion.width) + static_cast<size_t>(x);
      valid[p] = motionHolds(motion, p) && sourceOf(motion, p, x, y).inside ? 1.0f : 0.0f;
    }
  }
  return valid;
}

std::pair<int, int> warpSourceRows(const MotionField& motion) {
  checkField(motion);
  int first = motion.rowsOfFrame(), end = 0;
  for (int y = 0; y < motion.height; ++y)
    for (int x = 0; x < motion.width; ++x) {
      const size_t p = static_cast<size_t>(y) * static_cast<size_t>(motion.width) + static_cast<size_t>(x);
      const Source source = sourceOf(motion, p, x, y);
      if (!motionHolds(motion, p) || !source.inside) continue;
      // Bilinear taps at floor(y) and the row below; the nearest pixel is one of them.
      const int row = static_cast<int>(std::floor(std::max(source.y, 0.0f)));
      first = std::min(first, row);
      end = std::max(end, std::min(row + 2, motion.rowsOfFrame()));
    }
  return first < end ? std::pair{first, end} : std::pair{0, 0};
}

Planes warpPlanes(const Planes& neighbour, const MotionField& motion, WarpLookup lookup, int neighbourTop) {
  checkField(motion);
  const int frameRows = motion.rowsOfFrame();
  if (neighbour.width != motion.width || neighbour.height <= 0 || (motion.frameHeight == 0 && neighbour.height != frameRows))
    throw std::invalid_argument("warp: the neighbour frame is " + std::to_string(neighbour.width) + "x" +
                                std::to_string(neighbour.height) + " from row " + std::to_string(neighbourTop) +
                                ", its motion field " + std::to_string(motion.width) + "x" +
                                std::to_string(frameRows));
  if (neighbourTop < 0 || neighbourTop + neighbour.height > frameRows)
    throw std::logic_error("warp: the neighbour's rows " + std::to_string(neighbourTop) + " to " +
                           std::to_string(neighbourTop + neighbour.height) + " are not rows of a frame " +
                           std::to_string(frameRows) + " rows tall");
  for (const auto& plane : neighbour.channels)
    if (plane.size() != neighbour.pixelCount())
      throw std::invalid_argument("warp: a plane does not hold the frame's pixels");
  const int w = motion.width, h = motion.height;
  const size_t W = static_cast<size_t>(w);
  // A frame row of the source, as a row of `neighbour`.
  const auto held = [&](int frameRow) { return std::clamp(frameRow - neighbourTop, 0, neighbour.height - 1); };
  Planes out(w, h, static_cast<int>(neighbour.channels.size()));
  tbb::parallel_for(tbb::blocked_range<int>(0, h), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y != rows.end(); ++y) {
      for (int x = 0; x < w; ++x) {
        const size_t p = static_cast<size_t>(y) * W + static_cast<size_t>(x);
        const Source source = sourceOf(motion, p, x, y);
        const float sx = std::clamp(source.x, 0.0f, static_cast<float>(w - 1));
        const float sy = std::clamp(source.y, 0.0f, static_cast<float>(frameRows - 1));
        if (lookup == WarpLookup::Nearest) {
          const size_t q = static_cast<size_t>(held(static_cast<int>(std::lround(sy)))) * W +
                           static_cast<size_t>(std::lround(sx));
          for (size_t c = 0; c < out.channels.size(); ++c) out.channels[c][p] = neighbour.channels[c][q];
          continue;
        }
        const int x0 = static_cast<int>(std::floor(sx)), frameY0 = static_cast<int>(std::floor(sy));
        const float fx = sx - static_cast<float>(x0), fy = sy - static_cast<float>(frameY0);
        const int x1 = std::min(x0 + 1, w - 1), y0 = held(frameY0), y1 = held(std::min(frameY0 + 1, frameRows - 1));
        // Only taps of non-zero weight are read: an integer motion copies exactly, and a
        // broken value next to the source does not leak into it.
        const size_t taps[4] = {static_cast<size_t>(y0) * W + static_cast<size_t>(x0),
                                static_cast<size_t>(y0) * W + static_cast<size_t>(x1),
                                static_cast<size_t>(y1) * W + static_cast<size_t>(x0),
                                static_cast<size_t>(y1) * W + static_cast<size_t>(x1)};
        const float weights[4] = {(1.0f - fx) * (1.0f - fy), fx * (1.0f - fy), (1.0f - fx) * fy, fx * fy};
        for (size_t c = 0; c < out.channels.size(); ++c) {
          const std::vector<float>& in = neighbour.channels[c];
          float value = 0.0f;
          for (int k = 0; k < 4; ++k)
            if (weights[k] != 0.0f) value += weights[k] * in[taps[k]];
          out.channels[c][p] = value;
        }
      }
    }
  });
  return out;
}

}  // namespace pathfarm
