// `pathfarm preview DIR|FILE.exr... [--layer L]`: tone-mapped sRGB PNG previews of EXR
// frames (their beauty, or one layer such as `diffuse_indirect.color`), written next to them.
#include <spdlog/spdlog.h>

#include <algorithm>
#include <memory>

#include "cli/command.h"
#include "image/exr_io.h"
#include "image/png_preview.h"

namespace pathfarm {
namespace {

struct PreviewArguments {
  std::vector<std::string> inputs;
  float exposure = 1;
  std::string layer;  // empty: the beauty R, G, B
};

// The frame with `layer`.R/G/B (X/Y/Z, or Y alone as grey) as its beauty, to preview one
// buffer of one component; a whole channel name (`rerender.Y`) shows that channel as grey.
FrameImage layerAsBeauty(const FrameImage& frame, const std::string& layer) {
  const auto pick = [&](std::initializer_list<const char*> names) -> const std::vector<float>* {
    for (const char* name : names)
      if (frame.hasChannel(layer + "." + name)) return &frame.channel(layer + "." + name);
    return nullptr;
  };
  const std::vector<float>* r = pick({"R", "X"});
  const std::vector<float>* g = pick({"G", "Y"});
  const std::vector<float>* b = pick({"B", "Z"});
  if (!g && frame.hasChannel(layer)) g = &frame.channel(layer);
  if (!g)
    throw std::runtime_error("no layer or channel \"" + layer + "\" (channels " + layer + ".R/G/B, .X/Y/Z or .Y)");
  FrameImage preview(frame.width(), frame.height());
  preview.addChannel("R") = r ? *r : *g;
  preview.addChannel("G") = *g;
  preview.addChannel("B") = b ? *b : *g;
  return preview;
}

int runPreview(const PreviewArguments& arguments) {
  std::vector<std::filesystem::path> files;
  for (const std::filesystem::path input : arguments.inputs) {
    if (std::filesystem::is_directory(input)) {
      for (const auto& entry : std::filesystem::directory_iterator(input))
        if (entry.path().extension() == ".exr") files.push_back(entry.path());
    } else {
      files.push_back(input);
    }
  }
  std::sort(files.begin(), files.end());
  int failures = 0;
  for (const auto& file : files) {
    try {
      auto png = file;
      png.replace_extension(arguments.layer.empty() ? ".png" : "." + arguments.layer + ".png");
      const FrameImage frame = readExr(file);
      writePngPreview(png, arguments.layer.empty() ? frame : layerAsBeauty(frame, arguments.layer), arguments.exposure);
    } catch (const std::exception& e) {
      spdlog::error("{}", e.what());
      ++failures;
    }
  }
  spdlog::info("{} PNG previews written", files.size() - static_cast<size_t>(failures));
  return failures == 0 ? kExitOk : kExitFailure;
}

}  // namespace

std::vector<Command> addPreviewCommand(CLI::App& app) {
  auto arguments = std::make_shared<PreviewArguments>();
  CLI::App* preview = app.add_subcommand("preview", "write sRGB PNG previews of EXR frames (next to them)");
  preview->add_option("inputs", arguments->inputs, "EXR files or folders of them")->required();
  preview->add_option("--exposure", arguments->exposure, "exposure multiplier")->check(CLI::Range(1e-6, 1e6));
  preview->add_option("--layer", arguments->layer,
                      "preview one buffer instead of the beauty, e.g. diffuse_indirect.color or reflection.normal, or "
                      "one channel as grey, e.g. rerender.Y");
  return {{preview, [arguments] { return runPreview(*arguments); }}};
}

}  // namespace pathfarm
