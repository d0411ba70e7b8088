// A frame's final image (worker/filter_tasks.h): the stage output (filtered keyframe or
// interpolated frame) with every re-rendered pixel replaced by its full-sample render,
// denoised at full resolution among the other re-rendered pixels.
#include <algorithm>
#include <cmath>
#include <limits>

#include "image/exr_io.h"
#include "postproc/filters/component_denoiser.h"
#include "postproc/filters/decomposed_frame.h"
#include "worker/direct_emission.h"
#include "worker/failure_class.h"
#include "worker/filter_inputs.h"

namespace pathfarm::farm {
namespace {

constexpr int kRerenderSearchRadius = 5;

// The channels the final frame keeps: the beauty and every component's color.
std::vector<std::string> colorChannels(const FrameImage& frame) {
  std::vector<std::string> names = {"R", "G", "B"};
  for (const std::string& component : decompositionComponents(frame))
    for (const char* c : {"R", "G", "B"}) names.push_back(component + ".color." + c);
  return names;
}

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

}  // namespace

TaskOutput runCompositeTask(const Lease& lease, const std::vector<TaskInput>& inputs) {
  const int64_t frame = lease.params().frame();
  const TaskInput& stage = findInput(
      inputs, [&](const TaskInput& input) { return input.kind != TASK_RENDER_TILE && input.params.frame() == frame; },
      "the stage output of frame " + std::to_string(frame));
  const FrameImage& staged = stage.image;
  FrameImage result(staged.width(), staged.height());
  for (const std::string& name : colorChannels(staged)) result.addChannel(name) = staged.channel(name);
  result.attributes() = staged.attributes();

  FrameImage sparse(staged.width(), staged.height());
  std::vector<uint8_t> mask(staged.pixelCount(), 0);
  std::vector<PixelWindow> windows;
  for (const TaskInput& input : inputs) {
    if (input.kind != TASK_RENDER_TILE) continue;
    const PixelWindow& w = input.params.window();
    if (input.image.width() != w.x1() - w.x0() || input.image.height() != w.y1() - w.y0())
      throw BadInput("a re-render tile of frame " + std::to_string(frame) + " does not have its window's size");
    sparse.paste(input.image, w.x0(), w.y0());
    PixelWindow flagged;  // the bounding box of the tile's rendered pixels
    flagged.set_x0(w.x1());
    flagged.set_y0(w.y1());
    for (int y = w.y0(); y < w.y1(); ++y)
      for (int x = w.x0(); x < w.x1(); ++x) {
        const size_t local = static_cast<size_t>(y - w.y0()) * static_cast<size_t>(w.x1() - w.x0()) +
                             static_cast<size_t>(x - w.x0());
        if (!input.params.pixel_mask().empty() && input.params.pixel_mask()[local] == 0) continue;
        mask[static_cast<size_t>(y) * static_cast<size_t>(staged.width()) + static_cast<size_t>(x)] = 1;
        flagged.set_x0(std::min(flagged.x0(), x));
        flagged.set_y0(std::min(flagged.y0(), y));
        flagged.set_x1(std::max(flagged.x1(), x + 1));
        flagged.set_y1(std::max(flagged.y1(), y + 1));
      }
    if (flagged.x1() > flagged.x0()) windows.push_back(flagged);
    for (const auto& [key, value] : input.image.attributes()) sparse.attributes()[key] = value;
  }
  std::vector<float>& rerendered = result.addChannel("rerender.Y");
  if (!windows.empty()) {
    // Directly seen light skips the denoiser, as in the keyframes (worker/direct_emission.h).
    const bool decomposed = !decompositionComponents(sparse).empty();
    const FrameImage directLight = decomposed ? takeDirectEmission(sparse) : FrameImage();
    invalidateUnrendered(sparse, mask);
    DenoiseSettings settings;
    settings.label = "re-rendered pixels of frame " + std::to_string(frame);
    // They have the shot's full samples: a smaller search window than a keyframe's suffices.
    settings.spatialRadius = kRerenderSearchRadius;
    // Each tile is denoised with a margin wide enough for every patch its pixels compare.
    const int margin = settings.spatialRadius + settings.patch;
    for (const PixelWindow& w : windows) {
      const int x0 = std::max(0, w.x0() - margin), y0 = std::max(0, w.y0() - margin);
      const int x1 = std::min(staged.width(), w.x1() + margin), y1 = std::min(staged.height(), w.y1() + margin);
      const FrameImage denoised = denoiseFrame(sparse.crop(x0, y0, x1 - x0, y1 - y0), nullptr, nullptr, settings);
      for (const std::string& name : colorChannels(staged)) {
        const std::vector<float>& source = denoised.channel(name);
        std::vector<float>& target = result.channel(name);
        for (int y = w.y0(); y < w.y1(); ++y)
          for (int x = w.x0(); x < w.x1(); ++x) {
            const size_t p = static_cast<size_t>(y) * static_cast<size_t>(staged.width()) + static_cast<size_t>(x);
            if (mask[p]) target[p] = source[static_cast<size_t>(y - y0) * static_cast<size_t>(x1 - x0) +
                                            static_cast<size_t>(x - x0)];
          }
      }
    }
    if (decomposed) addDirectEmission(result, directLight, &mask);
    for (size_t p = 0; p < mask.size(); ++p) rerendered[p] = mask[p];
  }
  const size_t count = static_cast<size_t>(std::count(mask.begin(), mask.end(), 1));
  result.attributes()["pathfarm.rerender_pixels"] = std::to_string(count);
  result.attributes()["pathfarm.pipeline"] = lease.spec().pipeline();
  TaskOutput output;
  output.chunk = encodeExr(result);
  output.metrics["rerender_pixels"] = static_cast<double>(count);
  return output;
}

}  // namespace pathfarm::farm
