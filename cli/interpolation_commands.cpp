// `pathfarm interpolate K0.exr K1.exr --at S --out F.exr` and
// `pathfarm motionblur IN.exr --exposure E --out OUT.exr`.
#include <spdlog/spdlog.h>

#include <memory>

#include "cli/command.h"
#include "image/exr_io.h"
#include "postproc/interpolation/frame_interpolation.h"
#include "postproc/interpolation/irradiance_flow.h"
#include "postproc/motion_blur/motion_blur.h"

namespace pathfarm {
namespace {

struct InterpolateArguments {
  std::string k0, k1, out;
  std::vector<std::string> guides;
  float at = 0.5f;
  bool colorOnly = false;
};

struct MotionBlurArguments {
  std::string input, out;
  float exposure = 0.5f;
  MotionBlurSettings settings;
};

int runInterpolate(const InterpolateArguments& a) {
  return runReportingBadInput([&] {
    // The motion from K0 to K1 chains the per-frame motion of every rendered frame in
    // between (their guide features); consecutive keyframes need none.
    std::vector<FrameImage> chain{readExr(a.k0)};
    for (const std::string& guide : a.guides) chain.push_back(readExr(guide));
    chain.push_back(readExr(a.k1));
    InterpolationSettings settings;
    settings.colorOnly = a.colorOnly;
    ComponentMotions motions = concatenatePrimaryMotion(chain);
    // Reflectance moves with the geometry; irradiance (a shadow, a moving highlight) along
    // its own optical flow between the keyframes.
    if (!a.colorOnly) addIrradianceFlow(motions, chain.front(), chain.back(), FlowSettings{});
    const InterpolationResult result = interpolateFrameDetailed(chain.front(), chain.back(), motions, a.at, settings);
    writeExr(a.out, result.frame);
    spdlog::info("{} at {} between {} and {}: {:.2f} % of the pixels to re-render (rerender.Y)", a.out, a.at, a.k0,
                 a.k1, 100 * result.rerenderRate);
    return kExitOk;
  });
}

int runMotionBlur(const MotionBlurArguments& a) {
  return runReportingBadInput([&] {
    writeExr(a.out, motionBlur(readExr(a.input), a.exposure, a.settings));
    spdlog::info("{} -> {}: motion blur over {} of a frame", a.input, a.out, a.exposure);
    return kExitOk;
  });
}

}  // namespace

std::vector<Command> addInterpolationCommands(CLI::App& app) {
  auto interpolate = std::make_shared<InterpolateArguments>();
  CLI::App* i = app.add_subcommand("interpolate", "an in-between frame from two keyframes, per component");
  i->add_option("k0", interpolate->k0, "the earlier keyframe (decomposed EXR)")->required();
  i->add_option("k1", interpolate->k1, "the later keyframe")->required();
  i->add_option("--at", interpolate->at, "fraction between the keyframes, in (0, 1)")->required();
  i->add_option("--guides", interpolate->guides,
                "the rendered guide frames between the keyframes, in order (their motion is chained)");
  i->add_flag("--color-only", interpolate->colorOnly, "the baseline: the beauty along the primary motion");
  i->add_option("--out", interpolate->out, "output EXR (with rerender.Y)")->required();

  auto blur = std::make_shared<MotionBlurArguments>();
  CLI::App* b = app.add_subcommand("motionblur", "post-process motion blur, each component along its own motion");
  b->add_option("input", blur->input, "decomposed EXR")->required();
  b->add_option("--exposure", blur->exposure, "exposure as a fraction of a frame")->capture_default_str();
  b->add_option("--steps", blur->settings.steps, "time steps")->check(CLI::Range(1, 1024))->capture_default_str();
  b->add_option("--out", blur->out, "output EXR")->required();
  return {{i, [interpolate] { return runInterpolate(*interpolate); }}, {b, [blur] { return runMotionBlur(*blur); }}};
}

}  // namespace pathfarm
