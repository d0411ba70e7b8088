// Energy tests: a convex object in a white furnace, and a closed emitting room.
#include <gtest/gtest.h>

#include "renderer/integrators/frame_renderer.h"
#include "test_support.h"
#include "tests/renderer/sky_furnace.h"

namespace pathfarm {
namespace {

using test_support::sceneFromJson;

// A unit sphere filling the whole view, inside a constant environment of radiance 1.
std::string furnaceScene(const std::string& material) {
  return R"({
    "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "fov": 4},
    "materials": {"m": )" + material + R"(},
    "environment": {"radiance": 1},
    "shapes": [{"type": "sphere", "radius": 1, "material": "m"}]
  })";
}

TEST(WhiteFurnace, DiffuseSphereRendersItsAlbedo) {
  for (const float albedo : {0.2f, 0.5f, 0.9f}) {
    const Scene scene = sceneFromJson(furnaceScene(R"({"type": "diffuse", "reflectance": )" +
                                                   std::to_string(albedo) + "}"));
    const auto estimate = test_support::renderedMean(scene, 64, 8);
    EXPECT_NEAR(estimate.mean, albedo, 3 * estimate.standardError) << "albedo " << albedo;
    EXPECT_GT(estimate.standardError, 0);
  }
}

TEST(WhiteFurnace, SmoothGlassSphereIsInvisible) {
  // Fresnel reflection plus refraction lose nothing: every path ends in the environment.
  const Scene scene = sceneFromJson(furnaceScene(R"({"type": "dielectric", "ior": 1.5})"));
  const auto estimate = test_support::renderedMean(scene, 64, 64);
  EXPECT_NEAR(estimate.mean, 1.0, std::max(3 * estimate.standardError, 1e-4));
}

TEST(WhiteFurnace, PerfectMirrorReflectsEverything) {
  const Scene scene = sceneFromJson(furnaceScene(R"({"type": "conductor", "specular_color": 1})"));
  const auto estimate = test_support::renderedMean(scene, 4, 8);
  EXPECT_NEAR(estimate.mean, 1.0, 1e-5);
}

TEST(WhiteFurnace, RoughMaterialsNeverCreateEnergy) {
  // Rough conductors and rough glass are compensated for multiple scattering
  // (multiple_scattering.h) and keep nearly everything. None gains. Light stays inside a
  // sphere of ior 2.4 for about eight interactions, each keeping a little less than all (the
  // tables bound the single-scattering albedo from above by up to 1.5 %).
  struct Case {
    const char* material;
    double atLeast;
  };
  for (const Case& c :
       {Case{R"({"type": "rough_conductor", "specular_color": 1, "alpha": 0.3})", 0.97},
        Case{R"({"type": "rough_conductor", "specular_color": 1, "alpha": 1})", 0.97},
        Case{R"({"type": "rough_conductor", "specular_color": 1, "alpha": 0.8, "distribution": "beckmann"})", 0.97},
        Case{R"({"type": "rough_dielectric", "ior": 1.5, "alpha": 0.2})", 0.97},
        Case{R"({"type": "rough_dielectric", "ior": 1.5, "alpha": 1})", 0.97},
        Case{R"({"type": "rough_dielectric", "ior": 2.4, "alpha": 0.6, "distribution": "beckmann"})", 0.94},
        Case{R"({"type": "plastic", "reflectance": 1, "ior": 1.5})", 0.8},
        Case{R"({"type": "rough_plastic", "reflectance": 1, "ior": 1.5, "alpha": 0.2})", 0.8}}) {
    const Scene scene = sceneFromJson(furnaceScene(c.material));
    const auto estimate = test_support::renderedMean(scene, 64, 32);
    EXPECT_LE(estimate.mean, 1.0 + 3 * estimate.standardError) << c.material;
    EXPECT_GT(estimate.mean, c.atLeast) << c.material;
  }
}

// The sky furnace (sky_furnace.h) framed with the sky around the sphere: 0.5 on the
// sphere's pixels and 1.0 on the sky's, within 4 standard errors of the pixel means.
void expectSkyFurnace(test_support::SkySource sky) {
  RenderSettings settings;
  settings.width = settings.height = 24;
  settings.spp = 32;
  const auto means =
      test_support::skyFurnaceMeans(FrameRenderer(test_support::skyFurnaceScene(0, sky), settings).render(0));
  EXPECT_NEAR(means.sphere.mean, test_support::kSkyFurnaceSphere, 4 * means.sphere.standardError);
  EXPECT_NEAR(means.sky.mean, test_support::kSkyFurnaceSky, 1e-6);  // seen directly: no noise
  EXPECT_GT(means.sphere.standardError, 0);
}

TEST(WhiteFurnace, SphereInTheSkyReadsAlbedoAndTheSkyOne) { expectSkyFurnace(test_support::SkySource::Radiance); }
TEST(WhiteFurnace, SphereUnderAConstantMapReadsAlbedoAndTheSkyOne) {
  expectSkyFurnace(test_support::SkySource::ConstantMap);
}

// A closed cube of inward-facing emitting diffuse walls (emission Le, albedo rho) seen from
// inside: radiance is uniform and satisfies L = Le + rho L, so L = Le / (1 - rho) at
// every pixel. Any energy lost or created along long paths shows.
TEST(ClosedRoom, RadianceIsEmissionOverOneMinusAlbedo) {
  for (const float albedo : {0.5f, 0.8f}) {
    std::string walls;
    const char* placements[6] = {
        R"("translate": [0, 0, -1])",
        R"("translate": [0, 0, 1], "rotate": {"axis": [0, 1, 0], "angle": 180})",
        R"("translate": [-1, 0, 0], "rotate": {"axis": [0, 1, 0], "angle": 90})",
        R"("translate": [1, 0, 0], "rotate": {"axis": [0, 1, 0], "angle": -90})",
        R"("translate": [0, -1, 0], "rotate": {"axis": [1, 0, 0], "angle": -90})",
        R"("translate": [0, 1, 0], "rotate": {"axis": [1, 0, 0], "angle": 90})"};
    for (const char* placement : placements) {
      walls += std::string(walls.empty() ? "" : ",") +
               R"({"type": "rectangle", "size": [2, 2], "material": "wall", "emission": 1, "transform": {)" +
               placement + "}}";
    }
    const Scene scene = sceneFromJson(R"({
      "camera": {"position": [0, 0, 0.5], "look_at": [0.3, 0.2, -1], "fov": 90},
      "materials": {"wall": {"type": "diffuse", "reflectance": )" + std::to_string(albedo) + R"(}},
      "shapes": [)" + walls + "]}");
    const auto estimate = test_support::renderedMean(scene, 64, 1000);
    const double expected = 1.0 / (1.0 - albedo);
    EXPECT_NEAR(estimate.mean, expected, 3 * estimate.standardError) << "albedo " << albedo;
  }
}

}  // namespace
}  // namespace pathfarm
