// A frame's final image (worker/filter_tasks.h): the stage output (filtered keyframe or
// interpolated frame) with every re-rendered pixel replaced by its full-sample render,
// denoised at full resolution among the other re-rendered pixels. A frame taller than a
// filter window (contract/pipeline.h) is composited by a task per window, each holding only
// its rows, and joined by the frame's composite; denoising is cut at the filter windows'
// borders whichever task runs it, so the frame is the same bits however it is split.
#include <algorithm>
#include <limits>
#include <map>
#include <optional>
#include <stdexcept>
#include <tuple>

#include "contract/pipeline.h"
#include "image/exr_io.h"
#include "postproc/filters/component_denoiser.h"
#include "postproc/filters/decomposed_frame.h"
#include "postproc/filters/direct_emission.h"
#include "worker/failure_class.h"
#include "worker/filter_inputs.h"
#include "worker/final_frame.h"

namespace pathfarm::farm {
namespace {

constexpr int kRerenderSearchRadius = 5;
constexpr int kRerenderFireflyRadius = 8;

// Pixels outside `mask` carry no sample: their colors become NaN, which the denoiser reads
// as invalid (they neither contribute nor count).
void invalidateUnrendered(FrameImage& sparse, const std::vector<uint8_t>& mask) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (const std::string& name : sparse.channelNames()) {
    const bool sampled = name == "R" || name == "G" || name == "B" || name.rfind("variance.", 0) == 0 ||
                         name.find(".color.") != std::string::npos || name.find(".irradiance.") != std::string::npos ||
                         name.find(".variance.") != std::string::npos;
    if (!sampled) continue;
    std::vector<float>& values = sparse.channel(name);
    for (size_t p = 0; p < values.size(); ++p)
      if (!mask[p]) values[p] = nan;
  }
}

size_t localIndex(const PixelWindow& region, int x, int y) {
  return static_cast<size_t>(y - region.y0()) * static_cast<size_t>(region.x1() - region.x0()) +
         static_cast<size_t>(x - region.x0());
}

// Marks the pixels a re-render tile rendered (all of its window, or its pixel mask's) in the
// frame-wide `mask` and returns their bounding box (empty when none).
PixelWindow markRendered(const TaskParams& params, int width, std::vector<uint8_t>& mask) {
  const PixelWindow& w = params.window();
  PixelWindow flagged;
  flagged.set_x0(w.x1());
  flagged.set_y0(w.y1());
  for (int y = w.y0(); y < w.y1(); ++y)
    for (int x = w.x0(); x < w.x1(); ++x) {
      if (!params.pixel_mask().empty() && params.pixel_mask()[localIndex(w, x, y)] == 0) continue;
      mask[static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)] = 1;
      flagged.set_x0(std::min(flagged.x0(), x));
      flagged.set_y0(std::min(flagged.y0(), y));
      flagged.set_x1(std::max(flagged.x1(), x + 1));
      flagged.set_y1(std::max(flagged.y1(), y + 1));
    }
  return flagged;
}

// The re-rendered pixels of `region`, denoised among themselves (the pixels no tile
// rendered there are invalid) with their directly seen light kept out of the filter.
// Only the region is built: a frame-sized buffer of every tile channel would cost more
// memory than the denoising itself.
FrameImage denoisedRegion(const std::vector<const TaskInput*>& tiles, const std::vector<uint8_t>& mask, int width,
                          const PixelWindow& region, const DenoiseSettings& settings) {
  FrameImage sparse(region.x1() - region.x0(), region.y1() - region.y0());
  for (const TaskInput* tile : tiles) {
    const PixelWindow& w = tile->params.window();
    const int x0 = std::max(w.x0(), region.x0()), y0 = std::max(w.y0(), region.y0());
    const int x1 = std::min(w.x1(), region.x1()), y1 = std::min(w.y1(), region.y1());
    if (x1 <= x0 || y1 <= y0) continue;
    sparse.paste(tile->image().crop(x0 - w.x0(), y0 - w.y0(), x1 - x0, y1 - y0), x0 - region.x0(), y0 - region.y0());
    for (const auto& [key, value] : tile->image().attributes()) sparse.attributes()[key] = value;
  }
  std::vector<uint8_t> rendered(sparse.pixelCount());
  for (int y = region.y0(); y < region.y1(); ++y)
    for (int x = region.x0(); x < region.x1(); ++x)
      rendered[localIndex(region, x, y)] = mask[static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)];
  // Directly seen light skips the denoiser, as in the keyframes (postproc/filters/direct_emission.h).
  const bool decomposed = !decompositionComponents(sparse).empty();
  const FrameImage directLight = decomposed ? takeDirectEmission(sparse) : FrameImage();
  invalidateUnrendered(sparse, rendered);
  FrameImage denoised = denoiseFrame(sparse, nullptr, nullptr, settings);
  if (decomposed) addDirectEmission(denoised, directLight, &rendered);
  return denoised;
}

PixelWindow grown(const PixelWindow& w, int margin, int width, int height) {
  PixelWindow out;
  out.set_x0(std::max(0, w.x0() - margin));
  out.set_y0(std::max(0, w.y0() - margin));
  out.set_x1(std::min(width, w.x1() + margin));
  out.set_y1(std::min(height, w.y1() + margin));
  return out;
}

double area(const PixelWindow& w) { return static_cast<double>(w.x1() - w.x0()) * (w.y1() - w.y0()); }

// Windows side by side in a row of tiles, joined wherever one neighbourhood around both
// costs no more than two: each window is denoised in its neighbourhood, and neighbouring
// windows' neighbourhoods hold mostly the same pixels. Which windows are joined changes
// no bit (every neighbourhood holds all that decides its pixels, and NL-means sums its
// patch distances exactly wherever a neighbourhood starts).
std::vector<PixelWindow> joinedAlongRows(std::vector<PixelWindow> windows, int margin, int width, int height) {
  std::sort(windows.begin(), windows.end(), [](const PixelWindow& a, const PixelWindow& b) {
    return std::make_tuple(a.y0(), a.y1(), a.x0(), a.x1()) < std::make_tuple(b.y0(), b.y1(), b.x0(), b.x1());
  });
  std::vector<PixelWindow> joined;
  for (const PixelWindow& w : windows) {
    if (!joined.empty()) {
      PixelWindow& last = joined.back();
      PixelWindow both = last;
      both.set_x0(std::min(last.x0(), w.x0()));
      both.set_y0(std::min(last.y0(), w.y0()));
      both.set_y1(std::max(last.y1(), w.y1()));
      both.set_x1(std::max(last.x1(), w.x1()));
      if (area(grown(both, margin, width, height)) <=
          area(grown(last, margin, width, height)) + area(grown(w, margin, width, height))) {
        last = both;
        continue;
      }
    }
    joined.push_back(w);
  }
  return joined;
}


// `w`'s rows first .. end - 1 (empty when it has none there).
std::optional<PixelWindow> withinRows(PixelWindow w, int first, int end) {
  w.set_y0(std::max(w.y0(), first));
  w.set_y1(std::min(w.y1(), end));
  if (w.y1() <= w.y0()) return std::nullopt;
  return w;
}

std::string frameLabel(const Lease& lease) { return "frame " + std::to_string(lease.params().frame()); }

// The composite of the lease's rows (every row without a window): the stage output's final
// colors there, with their re-rendered pixels denoised; `mask` becomes the frame's
// re-render mask.
FrameImage compositedRows(const Lease& lease, std::vector<TaskInput>& inputs, std::vector<uint8_t>& mask) {
  const int64_t frame = lease.params().frame();
  const int width = lease.spec().width(), height = lease.spec().height();
  PixelWindow area;
  area.set_x1(width);
  area.set_y1(height);
  if (lease.params().has_window()) area = lease.params().window();
  if (area.x0() != 0 || area.x1() != width || area.y0() < 0 || area.y1() > height || area.y0() >= area.y1())
    throw BadInput("the composite of " + frameLabel(lease) + " is not of whole rows of the frame");
  const TaskInput& stage = findInput(
      inputs, [&](const TaskInput& input) { return input.kind != TASK_RENDER_TILE && input.params.frame() == frame; },
      "the stage output of " + frameLabel(lease));
  // The stage's final colors of these rows alone: a 1080p stage output holds about 80 channels.
  FrameImage result = stage.part({isFinalColorChannel, area.y0(), area.y1()});
  requireFinalColors(result, "the stage output of " + frameLabel(lease));
  if (result.width() != width)
    throw BadInput("the stage output of " + frameLabel(lease) + " is not " + std::to_string(width) + " pixels wide");

  std::vector<const TaskInput*> tiles;
  mask.assign(static_cast<size_t>(width) * static_cast<size_t>(height), 0);
  std::vector<PixelWindow> windows;
  for (const TaskInput& input : inputs) {
    if (input.kind != TASK_RENDER_TILE) continue;
    const PixelWindow& w = input.params.window();
    if (w.x0() < 0 || w.y0() < 0 || w.x1() > width || w.y1() > height || input.image().width() != w.x1() - w.x0() ||
        input.image().height() != w.y1() - w.y0())
      throw BadInput("a re-render tile of " + frameLabel(lease) + " does not have its window's size or place");
    const size_t area = static_cast<size_t>(w.x1() - w.x0()) * static_cast<size_t>(w.y1() - w.y0());
    if (!input.params.pixel_mask().empty() && input.params.pixel_mask().size() != area)
      throw BadInput("a re-render tile of " + frameLabel(lease) + " has a pixel mask of " +
                     std::to_string(input.params.pixel_mask().size()) + " bytes for " + std::to_string(area) +
                     " pixels");
    tiles.push_back(&input);
    const PixelWindow flagged = markRendered(input.params, width, mask);
    if (flagged.x1() > flagged.x0()) windows.push_back(flagged);
  }
  DenoiseSettings settings;
  settings.label = "re-rendered pixels of " + frameLabel(lease);
  // They have the shot's full samples: a smaller search window than a keyframe's suffices.
  settings.spatialRadius = kRerenderSearchRadius;
  // A firefly in a small re-rendered clump would light the whole clump; spread, it lights
  // what its share of a Gaussian covers. The spread is kept short, as the neighbourhood
  // below must hold everything that decides a window's pixels (else the frame would
  // depend on how the re-render was cut into tiles).
  settings.fireflies.maxRadius = kRerenderFireflyRadius;
  // Each window is denoised with a margin wide enough for every patch its pixels compare
  // and every firefly whose spread reaches them.
  const int margin = settings.spatialRadius + settings.patch + fireflyReach(settings.fireflies);
  // The scheduler gives a window's composite the tiles within kCompositeHalo of its rows.
  if (margin > kCompositeHalo) throw std::logic_error("the composite's denoise reaches beyond kCompositeHalo");
  for (const RowWindow& rows : filterWindowsOf(lease.spec())) {
    const int first = std::max(rows.first, area.y0()), end = std::min(rows.end, area.y1());
    if (first >= end) continue;
    std::vector<PixelWindow> inRows;
    for (const PixelWindow& w : windows)
      if (const auto clipped = withinRows(w, first, end)) inRows.push_back(*clipped);
    for (const PixelWindow& w : joinedAlongRows(inRows, margin, width, height)) {
      const PixelWindow region = grown(w, margin, width, height);
      // Only the window's pixels are kept: the filter need not finish the rest.
      settings.onlyWithin = NlMeansArea{w.x0() - region.x0(), w.y0() - region.y0(), w.x1() - region.x0(),
                                        w.y1() - region.y0()};
      FrameImage denoised = denoisedRegion(tiles, mask, width, region, settings);
      for (const std::string& name : result.channelNames()) {
        const std::vector<float>& source = denoised.channel(name);
        std::vector<float>& target = result.channel(name);
        for (int y = w.y0(); y < w.y1(); ++y)
          for (int x = w.x0(); x < w.x1(); ++x) {
            const size_t p = static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x);
            const size_t inResult = p - static_cast<size_t>(area.y0()) * static_cast<size_t>(width);
            if (mask[p]) target[inResult] = source[localIndex(region, x, y)];
          }
      }
    }
  }
  return result;
}

// The frame's composite from its windows' composites: written from them a window at a
// time (a 4K final frame is more than a gigabyte), with the re-render they flagged recorded.
TaskOutput joinedWindows(const Lease& lease, std::vector<TaskInput>& inputs) {
  const std::string label = "a window's composite of " + frameLabel(lease);
  TaskOutput output;
  const std::vector<uint8_t> mask = joinRowWindows(
      lease, inputs, "composites", [label](const FrameImage& rows) { requireFinalColors(rows, label); }, output).mask;
  output.compression = ExrCompression::Small;  // the shot's frame
  std::map<std::string, std::string> record;
  recordRerender(record, static_cast<size_t>(std::count(mask.begin(), mask.end(), 1)), lease.spec().pipeline(),
                 output);
  addJoinedAttributes(output, std::move(record));
  return output;
}

}  // namespace

TaskOutput runCompositeTask(const Lease& lease, std::vector<TaskInput>& inputs) {
  if (joinsWindows(lease, inputs)) return joinedWindows(lease, inputs);
  std::vector<uint8_t> mask;
  FrameImage result = compositedRows(lease, inputs, mask);
  if (!lease.params().has_window()) return finishedFinalFrame(std::move(result), mask, lease.spec().pipeline());
  // A window: its rows with their re-render mask, for the frame's composite to join.
  const PixelWindow& w = lease.params().window();
  const auto width = static_cast<ptrdiff_t>(lease.spec().width());
  addRerenderMask(result, std::vector<uint8_t>(mask.begin() + w.y0() * width, mask.begin() + w.y1() * width));
  TaskOutput output;
  output.chunk = encodeExr(result, ExrCompression::Fast);
  return output;
}

}  // namespace pathfarm::farm
