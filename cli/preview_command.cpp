// `pathfarm preview DIR|FILE.exr...`: tone-mapped sRGB PNG previews of EXR frames,
// written next to them.
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
};

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
      png.replace_extension(".png");
      writePngPreview(png, readExr(file), arguments.exposure);
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
  return {{preview, [arguments] { return runPreview(*arguments); }}};
}

}  // namespace pathfarm
