// Every integrator renders a character: the creature suite scene (a skinned tentacle, a
// morphing blob, a mirror and glass, motion blur) gives finite, non-negative values in
// every channel, and the frame as a whole is lit.
#include <gtest/gtest.h>

#include <cmath>

#include "renderer/metropolis/metropolis_renderer.h"
#include "renderer/scene/scene_loader.h"
#include "renderer/setup/integrator_factory.h"
#include "test_support.h"
#include "tests/renderer/metropolis/metropolis_test_support.h"

namespace pathfarm {
namespace {

void expectFiniteAndLit(const FrameImage& image, std::string_view integrator) {
  for (const std::string& name : image.channelNames())
    for (const float v : image.channel(name)) ASSERT_TRUE(std::isfinite(v)) << integrator << " " << name;
  double sum = 0;
  for (const float v : image.channel("G")) {
    ASSERT_GE(v, 0.0f) << integrator;
    sum += v;
  }
  EXPECT_GT(sum / static_cast<double>(image.channel("G").size()), 0.05) << integrator;
}

TEST(DeformingIntegrators, EveryIntegratorRendersTheCreatureFinite) {
  const Scene scene = loadScene(test_support::sourceDir() / "scenes/creature/scene.json");
  RenderSettings settings = RenderSettings::defaultsOf(scene);
  settings.width = 32;
  settings.height = 18;
  settings.spp = 2;
  settings.maxDepth = 5;
  int rendered = 0;
  for (const IntegratorTraits& traits : allIntegrators()) {
    if (traits.rendersWindows) {
      const MetropolisMethod method = parseMetropolisMethod(std::string(traits.name));
      MetropolisSettings metropolis = test_support::smallMetropolisSettings(method, 2);
      metropolis.bootstrapSamples = 1000;
      const int frames = method == MetropolisMethod::PathSpace ? 1 : 2;  // mlt renders frame by frame
      for (const FrameImage& frame : MetropolisRenderer(scene, metropolis).render({6, frames}))
        expectFiniteAndLit(frame, traits.name);
    } else {
      expectFiniteAndLit(makeFrameIntegrator(traits.name, scene, settings)->render(6), traits.name);
    }
    ++rendered;
  }
  EXPECT_EQ(rendered, 7);
}

}  // namespace
}  // namespace pathfarm
