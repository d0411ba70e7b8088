// "reference_spp": "auto": the reference's samples follow from a pilot's variance so that
// the reference's own noise, measured on the reference itself, is at most a tenth of the
// error it is there to resolve.
#include "client/reference_choice.h"

#include <gtest/gtest.h>

#include <fstream>

#include "client/shot_preparation.h"
#include "postproc/metrics/relmse.h"
#include "renderer/integrators/frame_renderer.h"
#include "renderer/scene/scene_loader.h"
#include "test_support.h"

namespace pathfarm::farm {
namespace {

TEST(ReferenceChoice, TheSppIsTheFirstPowerOfTwoWhoseNoiseIsATenthOfTheError) {
  // pt's relMSE at 1 spp of 1.6: a tenth of 0.001 needs 16000 spp, so 16384.
  EXPECT_EQ(resolvingReferenceSpp(1.6, 0.001, 64), 16384);
  EXPECT_EQ(resolvingReferenceSpp(1.6, 0.0016, 64), 16384) << "10000: the next power of two";
  EXPECT_EQ(resolvingReferenceSpp(1.6, 1.0, 64), 64) << "never fewer samples than the shot's own";
  EXPECT_EQ(resolvingReferenceSpp(1.6, 1e-9, 64), kMaxAutoReferenceSpp);
}

std::filesystem::path autoReferenceShot(const std::string& pipeline) {
  const auto folder = test_support::processTemporaryFolder("pathfarm_reference_choice");
  std::filesystem::create_directories(folder);
  const auto file = folder / (pipeline + ".json");
  std::ofstream(file) << R"({"scene": ")" << (test_support::sourceDir() / "scenes/cornell/scene.json").string()
                      << R"(", "frames": {"start": 0, "end": 3}, "resolution": [64, 64], "spp": 4,
      "max_depth": 6, "keyframe_interval": 1, "pipeline": ")" << pipeline << R"(", "reference_spp": "auto"})";
  return file;
}

TEST(ReferenceChoice, AnAutoReferencesErrorIsATenthOfPtsAtTheShotsSpp) {
  const ShotFile file = ShotFile::load(autoReferenceShot("pt"));
  EXPECT_EQ(file.spec().reference_spp(), kAutoReferenceSpp) << "chosen only once the pipeline is known";
  const ShotSpec spec = preparedShot(file);
  EXPECT_EQ(spec.reference_spp(), 64) << "10 x 4 spp, rounded up to a power of two: " << spec.reference_reason();

  // Measured against a 1024-spp truth (less the truth's own noise), independently of the
  // rule: pt's error at the shot's spp (a mean of four renders) and the reference's.
  const Scene scene = loadScene(spec.scene());
  RenderSettings settings;
  settings.width = spec.width();
  settings.height = spec.height();
  settings.maxDepth = spec.max_depth();
  settings.spp = 1024;
  settings.firstSample = 1u << 30;
  const FrameImage truth = FrameRenderer(scene, settings).render(1);
  const auto errorOf = [&](int spp, uint32_t firstSample) {
    settings.spp = spp;
    settings.firstSample = firstSample;
    return relMse(FrameRenderer(scene, settings).render(1), truth) - expectedRelMse(truth);
  };
  double ptError = 0;
  for (uint32_t run = 0; run < 4; ++run) ptError += errorOf(spec.spp(), run * 4) / 4;
  EXPECT_LE(errorOf(spec.reference_spp(), kIndependentFirstSample), ptError / 10) << "pt's error " << ptError;

  // d is expected to reach about a sixteenth of pt's error: a reference 16 times longer.
  const ShotSpec filtered = preparedShot(ShotFile::load(autoReferenceShot("d")));
  EXPECT_EQ(filtered.reference_spp(), 1024) << filtered.reference_reason();
}

TEST(ReferenceChoice, AutosPredictedErrorIsResolvedFromAPilotsVariance) {
  ShotSpec spec = preparedShot(ShotFile::load(autoReferenceShot("pt")));
  const Scene scene = loadScene(spec.scene());
  spec.set_reference_spp(kAutoReferenceSpp);
  spec.set_predicted_relmse(0.02);
  const ShotSpec coarse = withReferenceChosen(spec, scene);
  spec.set_predicted_relmse(0.005);
  const ShotSpec fine = withReferenceChosen(spec, scene);
  EXPECT_EQ(fine.reference_spp(), 4 * coarse.reference_spp()) << "a quarter of the error, four times the samples";
  EXPECT_NE(fine.reference_reason().find("pilot of frame 1"), std::string::npos) << fine.reference_reason();
}

TEST(ReferenceChoice, AWordOtherThanAutoIsRefused) {
  const auto file = autoReferenceShot("pt");
  std::ofstream(file) << R"({"scene": ")" << (test_support::sourceDir() / "scenes/cornell/scene.json").string()
                      << R"(", "reference_spp": "lots"})";
  try {
    ShotFile::load(file);
    FAIL() << "accepted";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("expected a number of samples or \"auto\""), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace pathfarm::farm
