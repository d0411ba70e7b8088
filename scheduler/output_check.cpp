#include "scheduler/output_check.h"

#include <exception>

#include "image/exr_io.h"
#include "image/size_text.h"

namespace pathfarm::farm {

std::string refusalOfOutput(const std::filesystem::path& file, TaskKind kind, const TaskParams& params,
                            const ShotSpec& spec) {
  if (kind == TASK_NOOP || kind == TASK_EVALUATE) return {};
  ExrScan image;
  try {
    image = scanExrFile(file, "the output");
  } catch (const std::exception& e) {
    return e.what();
  }
  const std::string size = sizeText(image.width, image.height);
  if (kind == TASK_RENDER_TILE || kind == TASK_GRADIENT_TILE || (kind == TASK_ASSEMBLE_FRAME && params.has_window())) {
    const auto& window = params.window();
    const int width = window.x1() - window.x0(), height = window.y1() - window.y0();
    if (image.width != width || image.height != height)
      return "the tile is " + size + ", its window " + sizeText(width, height);
  } else if (image.width > spec.width() || image.height > spec.height()) {
    return "the image is " + size + ", larger than the shot's " + sizeText(spec.width(), spec.height()) + " frame";
  }
  if (!image.firstNonFinite.empty()) return "a non-finite value in " + image.firstNonFinite;
  return {};
}

}  // namespace pathfarm::farm
