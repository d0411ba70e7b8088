// PathDecomposer starts each sample from nothing, though it clears only the components
// the previous sample touched (SampleComponents::touched).
#include "renderer/decomposition/path_decomposer.h"

#include <gtest/gtest.h>

namespace pathfarm {
namespace {

LobeList oneDiffuseLobe() {
  LobeList lobes;
  lobes.lobes[0] = {LobeSymbol::D, false};
  lobes.count = 1;
  return lobes;
}

TEST(PathDecomposer, ASampleStartsWithNothingOfTheSampleBefore) {
  const Decomposition decomposition = Decomposition::standard();
  SampleComponents out;
  PathDecomposer decomposer(decomposition, out);
  const int diffuseDirect = 0;  // ED, the first of the standard components

  // Sample 1: light reaching the eye after one diffuse vertex.
  LobeValues f;
  f.value[0] = Rgb(0.5f);
  decomposer.addLightSample(oneDiffuseLobe(), f, Rgb(2.0f), false);
  VertexFeatures vertex;
  vertex.depth = 3;
  decomposer.scatter(oneDiffuseLobe(), vertex, nullptr);  // the path ends here
  ASSERT_EQ(out.color[diffuseDirect].r, 1.0f);
  ASSERT_TRUE(out.hasFeatures(diffuseDirect));
  ASSERT_NE(out.touched, 0u);

  // Sample 2: the eye sees an emitter directly; nothing of sample 1 may remain.
  decomposer.begin();
  EXPECT_EQ(out.touched, 0u);
  for (int k = 0; k < decomposition.size(); ++k) {
    EXPECT_TRUE(out.color[static_cast<size_t>(k)].isBlack()) << decomposition.name(k);
    EXPECT_TRUE(out.direct[static_cast<size_t>(k)].isBlack()) << decomposition.name(k);
    EXPECT_FALSE(out.hasFeatures(static_cast<size_t>(k))) << decomposition.name(k);
  }
  decomposer.addEmission(Rgb(4.0f));
  Rgb total;
  for (int k = 0; k < decomposition.size(); ++k) {
    total += out.color[static_cast<size_t>(k)];
    // What the sample touched is exactly where it put light or features.
    const bool touched = (out.touched >> k) & 1u;
    EXPECT_EQ(touched, !out.color[static_cast<size_t>(k)].isBlack()) << decomposition.name(k);
  }
  EXPECT_EQ(total.r, 4.0f);
  EXPECT_TRUE(out.color[diffuseDirect].isBlack());
}

}  // namespace
}  // namespace pathfarm
