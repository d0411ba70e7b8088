// The sampling contract: a frame is the same bits for any thread count and tile size.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>

#include "image/exr_io.h"
#include "renderer/integrators/frame_renderer.h"
#include "test_support.h"

namespace pathfarm {
namespace {

std::string fileBytes(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(Determinism, ThreadsAndTileSizesGiveIdenticalBytes) {
  const Scene scene = loadScene(test_support::sourceDir() / "scenes/cornell/scene.json");
  RenderSettings settings;
  settings.width = 48;
  settings.height = 40;
  settings.spp = 4;
  settings.maxDepth = 6;
  const auto folder = test_support::processTemporaryFolder("pathfarm_determinism");
  std::filesystem::create_directories(folder);

  std::vector<std::string> files;
  for (const auto& [threads, tile] : {std::pair{1, 8}, std::pair{2, 16}, std::pair{2, 7}}) {
    settings.threads = threads;
    settings.tileSize = tile;
    const FrameRenderer renderer(scene, settings);
    // Frame 7: every animated object is moving, under motion blur.
    const auto file = folder / (std::to_string(threads) + "threads_" + std::to_string(tile) + "tile.exr");
    writeExr(file, renderer.render(7));
    files.push_back(fileBytes(file));
  }
  ASSERT_GT(files[0].size(), 1000u);
  EXPECT_EQ(files[0], files[1]);
  EXPECT_EQ(files[0], files[2]);
  std::filesystem::remove_all(folder);
}

TEST(Determinism, WindowsPastedTogetherEqualTheWholeFrame) {
  const Scene scene = loadScene(test_support::sourceDir() / "scenes/cornell/scene.json");
  RenderSettings settings;
  settings.width = 30;
  settings.height = 22;
  settings.spp = 3;
  const FrameImage whole = FrameRenderer(scene, settings).render(5);

  FrameImage joined(settings.width, settings.height);
  // Uneven windows, as a farm's edge tiles are.
  for (const PixelWindow window : {PixelWindow{0, 0, 16, 16}, PixelWindow{16, 0, 30, 16},
                                   PixelWindow{0, 16, 16, 22}, PixelWindow{16, 16, 30, 22}}) {
    joined.paste(FrameRenderer(scene, settings).renderWindow(5, window), window.x0, window.y0);
  }
  ASSERT_EQ(joined.channelNames(), whole.channelNames());
  for (const std::string& name : whole.channelNames()) EXPECT_EQ(joined.channel(name), whole.channel(name)) << name;

  EXPECT_THROW(FrameRenderer(scene, settings).renderWindow(5, {20, 0, 31, 5}), std::invalid_argument);
}

TEST(Determinism, DifferentFramesAndSeedsDiffer) {
  Scene scene = loadScene(test_support::sourceDir() / "scenes/cornell/scene.json");
  RenderSettings settings;
  settings.width = settings.height = 16;
  settings.spp = 2;
  const FrameRenderer renderer(scene, settings);
  const auto a = renderer.render(3).channel("R");
  EXPECT_NE(a, renderer.render(4).channel("R"));
  scene.seed = 99;
  const FrameRenderer reseeded(scene, settings);
  EXPECT_NE(a, reseeded.render(3).channel("R"));
}

TEST(Determinism, SampleIndicesStartWhereTheSettingsSay) {
  // Two samples from index 0 are the mean of one from index 0 and one from index 1: the
  // render draws exactly the samples its first index names. A reference starts at
  // kIndependentFirstSample, beyond any shot's 2^20 spp, so it shares none of them.
  const Scene scene = loadScene(test_support::sourceDir() / "scenes/cornell/scene.json");
  RenderSettings settings;
  settings.width = settings.height = 12;
  settings.spp = 2;
  const auto both = FrameRenderer(scene, settings).render(3).channel("G");
  settings.spp = 1;
  const auto first = FrameRenderer(scene, settings).render(3).channel("G");
  settings.firstSample = 1;
  const auto second = FrameRenderer(scene, settings).render(3).channel("G");
  for (size_t p = 0; p < both.size(); ++p) ASSERT_NEAR(both[p], 0.5f * (first[p] + second[p]), 1e-5f * (1 + both[p]));
  settings.firstSample = kIndependentFirstSample;
  const FrameImage reference = FrameRenderer(scene, settings).render(3);
  EXPECT_NE(reference.channel("G"), first);
  EXPECT_NE(reference.channel("G"), second);
  EXPECT_EQ(reference.attributes().at("pathfarm.first_sample"), std::to_string(kIndependentFirstSample));
}

}  // namespace
}  // namespace pathfarm
