// The metallic-roughness material end to end in the path tracer: a sphere of it in a
// constant environment of radiance 1 (the white furnace) reads at most 1, exactly 1 for a
// white mirror and for smooth white transmission, where every path leaves with weight 1;
// and the automatic decomposition plans the components its lobes call for.
#include <gtest/gtest.h>

#include "renderer/setup/auto_decomposition.h"
#include "renderer/integrators/frame_renderer.h"
#include "test_support.h"

namespace pathfarm {
namespace {


// A unit sphere filling the view (as in furnace_test.cpp), with a white base colour.
Scene furnace(const std::string& parameters) {
  return test_support::sceneFromJson(R"({
    "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "fov": 4},
    "materials": {"m": {"type": "metallic_roughness", "base_color": 1, )" + parameters + R"(}},
    "environment": {"radiance": 1},
    "shapes": [{"type": "sphere", "radius": 1, "material": "m"}]
  })");
}

TEST(MetallicRoughnessFurnace, WhiteMirrorReflectsEverything) {
  // Schlick with F0 = 1 is one at every angle: no noise, no loss.
  const auto estimate = test_support::renderedMean(furnace(R"("metallic": 1, "roughness": 0)"), 4, 8);
  EXPECT_NEAR(estimate.mean, 1.0, 1e-5);
}

TEST(MetallicRoughnessFurnace, SmoothWhiteTransmissionLosesNothing) {
  // Reflection F and straight transmission (1 - F) rho sum to one at each wall.
  const auto estimate = test_support::renderedMean(furnace(R"("metallic": 0, "roughness": 0, "transmission": 1)"), 16, 64);
  EXPECT_NEAR(estimate.mean, 1.0, 1e-4);
}

TEST(MetallicRoughnessFurnace, RoughVariantsNeverCreateEnergy) {
  // White metals keep their energy at every roughness: what single-scattering GGX loses
  // (about two thirds at roughness 1) the compensation of multiple_scattering.h returns,
  // less its table's margin. The opaque dielectric keeps nearly everything too: its
  // diffuse base takes what the coating leaves, less the 1-2 % of the albedo bound. The
  // other lower bounds only say the sphere is not dark: the thin-walled transmission is
  // single scattering, and light crossing the thin sphere meets it at least twice.
  struct Case {
    const char* parameters;
    double atLeast;
  };
  for (const Case& c : {Case{R"("metallic": 0, "roughness": 0.5)", 0.95},
                        Case{R"("metallic": 0, "roughness": 1)", 0.95},
                        Case{R"("metallic": 1, "roughness": 0.3)", 0.97},
                        Case{R"("metallic": 1, "roughness": 1)", 0.97},
                        Case{R"("metallic": 0.5, "roughness": 0.7, "transmission": 0.5)", 0.5},
                        Case{R"("metallic": 0, "roughness": 1, "transmission": 1, "ior": 1.33)", 0.05},
                        Case{R"("metallic": 0, "roughness": 0.05, "transmission": 0.5)", 0.95}}) {
    const auto estimate = test_support::renderedMean(furnace(c.parameters), 64, 32);
    EXPECT_LE(estimate.mean, 1.0 + 3 * estimate.standardError) << c.parameters;
    EXPECT_GT(estimate.mean, c.atLeast) << c.parameters;
    EXPECT_GT(estimate.standardError, 0) << c.parameters;
  }
}

bool plans(const Decomposition& d, const std::string& name) {
  for (const Component& c : d.components())
    if (c.name == name) return true;
  return false;
}

TEST(MetallicRoughnessFurnace, AutomaticDecompositionFollowsTheLobes) {
  const Decomposition opaque = chooseDecomposition(furnace(R"("metallic": 0, "roughness": 0.2)"));
  EXPECT_TRUE(plans(opaque, "reflection"));
  EXPECT_FALSE(plans(opaque, "transmission"));
  const Decomposition rough = chooseDecomposition(furnace(R"("metallic": 0, "roughness": 0.6)"));
  EXPECT_FALSE(plans(rough, "reflection"));
  const Decomposition glass = chooseDecomposition(furnace(R"("metallic": 0, "roughness": 0, "transmission": 0.5)"));
  EXPECT_TRUE(plans(glass, "reflection"));
  EXPECT_TRUE(plans(glass, "transmission"));
}

}  // namespace
}  // namespace pathfarm
