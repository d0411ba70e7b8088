// `pathfarm denoise` and `pathfarm upsample`: the postproc filters on EXR frames.
#include <spdlog/spdlog.h>

#include <memory>
#include <optional>

#include "cli/command.h"
#include "image/exr_io.h"
#include "postproc/filters/component_denoiser.h"
#include "postproc/filters/component_upsampler.h"

namespace pathfarm {
namespace {

struct DenoiseArguments {
  std::string input, previous, next, out;
  std::string mode = "decomposition";
  std::optional<int> radius;
  DenoiseSettings settings;
};

struct UpsampleArguments {
  std::string input, guide, out;
  UpsampleSettings settings;
};


int runDenoise(DenoiseArguments& a) {
  return runReportingBadInput([&] {
    a.settings.mode = parseDenoiseMode(a.mode);
    if (a.radius) a.settings.spatialRadius = a.settings.temporalRadius = *a.radius;
    a.settings.label = a.input;
    const FrameImage current = readExr(a.input);
    std::optional<FrameImage> previous, next;
    if (!a.previous.empty()) {
      previous = readExr(a.previous);
      a.settings.previousLabel = a.previous;
    }
    if (!a.next.empty()) {
      next = readExr(a.next);
      a.settings.nextLabel = a.next;
    }
    const FrameImage result =
        denoiseFrame(current, previous ? &*previous : nullptr, next ? &*next : nullptr, a.settings);
    writeExr(a.out, result);
    spdlog::info("{} -> {} ({})", a.input, a.out, result.attributes().at("pathfarm.denoise"));
    return kExitOk;
  });
}

int runUpsample(UpsampleArguments& a) {
  return runReportingBadInput([&] {
    const FrameImage low = readExr(a.input);
    FrameImage result = readExr(a.guide);  // the full-resolution features travel along
    const FrameImage upsampled = upsampleFrame(low, result, a.settings);
    result.paste(upsampled, 0, 0);
    result.attributes() = upsampled.attributes();
    writeExr(a.out, result);
    const auto flagged = std::stoull(upsampled.attributes().at("pathfarm.rerender_pixels"));
    spdlog::info("{} -> {}: {} pixels ({:.3f} %) flagged for re-rendering in rerender.Y", a.input, a.out, flagged,
                 100.0 * static_cast<double>(flagged) / static_cast<double>(result.pixelCount()));
    return kExitOk;
  });
}

}  // namespace

std::vector<Command> addFilterCommands(CLI::App& app) {
  auto denoise = std::make_shared<DenoiseArguments>();
  CLI::App* d = app.add_subcommand("denoise", "joint NL-means per path-space component (Zimmer et al. 2015)");
  d->add_option("input", denoise->input, "decomposed EXR frame")->required();
  d->add_option("--prev", denoise->previous, "the previous frame (spatio-temporal filtering)");
  d->add_option("--next", denoise->next, "the next frame (spatio-temporal filtering)");
  d->add_option("--out", denoise->out, "denoised EXR")->required();
  d->add_option("--mode", denoise->mode, "decomposition, color (the beauty with primary features) or no-features")->capture_default_str();
  d->add_option("--radius", denoise->radius, "search radius r (default 10 spatial, 5 with neighbours)")
      ->check(CLI::Range(0, 64));
  d->add_option("--patch", denoise->settings.patch, "patch radius f")->check(CLI::Range(0, 16))->capture_default_str();
  d->add_option("--kc", denoise->settings.kc, "color sensitivity")->capture_default_str();
  d->add_option("--kf", denoise->settings.kf, "feature sensitivity")->capture_default_str();
  d->add_option("--tau", denoise->settings.tau, "feature normalization floor (the paper's tau^2)")->capture_default_str();
  d->add_option("--alpha", denoise->settings.alpha,
                "variance cancellation (the farm's d and di keyframes use 1, quarter-spp keyframes 4)")
      ->check(CLI::Range(0.0f, 16.0f))
      ->capture_default_str();
  d->add_flag("--depth", denoise->settings.useDepth, "use depth as a feature too");
  d->add_flag("--keep-fireflies{false}", denoise->settings.spreadFireflies,
              "filter fireflies with the frame instead of spreading their light over their surface");

  auto upsample = std::make_shared<UpsampleArguments>();
  CLI::App* u = app.add_subcommand("upsample", "guided-filter joint upsampling per component (He et al. 2013)");
  u->add_option("input", upsample->input, "low-resolution decomposed EXR")->required();
  u->add_option("--guide", upsample->guide, "full-resolution features (a decomposed EXR)")->required();
  u->add_option("--out", upsample->out, "upsampled EXR")->required();
  u->add_option("--factor", upsample->settings.guided.factor, "integer factor")->check(CLI::Range(1, 16))->capture_default_str();
  u->add_option("--radius", upsample->settings.guided.radius, "window radius in low-resolution pixels")
      ->check(CLI::Range(0, 64))
      ->capture_default_str();
  u->add_option("--epsilon", upsample->settings.guided.epsilon, "regularization")->capture_default_str();
  return {{d, [denoise] { return runDenoise(*denoise); }}, {u, [upsample] { return runUpsample(*upsample); }}};
}

}  // namespace pathfarm
