// The composite task replaces a frame's re-rendered pixels by their render, denoised among
// themselves. It builds only the neighbourhood of each re-rendered window; the pixels it
// writes must be those of denoising the whole frame of re-rendered pixels at once.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>

#include "contract/pipeline.h"
#include "image/exr_io.h"
#include "postproc/filters/component_denoiser.h"
#include "postproc/filters/decomposed_frame.h"
#include "task_output_bytes.h"
#include "test_support.h"
#include "postproc/filters/direct_emission.h"
#include "worker/task_runner.h"

namespace pathfarm::farm {
namespace {

constexpr int kSize = 40;

FrameImage renderCornell(int spp) {
  return test_support::renderDecomposed("scenes/cornell/scene.json", kSize, kSize, spp, 0);
}

struct Tile {
  PixelWindow window;
  std::string mask;  // empty: every pixel
};

PixelWindow window(int x0, int y0, int x1, int y1) {
  PixelWindow w;
  w.set_x0(x0);
  w.set_y0(y0);
  w.set_x1(x1);
  w.set_y1(y1);
  return w;
}

TEST(CompositeTask, ReRenderedPixelsAreThoseOfDenoisingTheWholeSparseFrame) {
  const FrameImage staged = renderCornell(1);
  const FrameImage rendered = renderCornell(16);
  // Three tiles: one re-rendered below its first two rows, its neighbour in part (a
  // diagonal band from the top, so that its window comes first in a row though it lies to
  // the right), and one far away re-rendered whole.
  std::vector<Tile> tiles = {{window(0, 0, 16, 16), std::string(256, '\0')},
                             {window(16, 0, 32, 16), std::string(256, '\0')}, {window(24, 24, 40, 40), ""}};
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x) {
      tiles[0].mask[static_cast<size_t>(y * 16 + x)] = y >= 2 ? 1 : 0;
      tiles[1].mask[static_cast<size_t>(y * 16 + x)] = std::abs(x - y) < 3 ? 1 : 0;
    }

  std::map<std::string, std::string> chunks = {{"stage", encodeExr(staged, ExrCompression::Fast)}};
  Lease lease;
  lease.set_kind(TASK_COMPOSITE);
  lease.mutable_spec()->set_pipeline(PIPELINE_DUI);
  lease.mutable_spec()->set_width(kSize);
  lease.mutable_spec()->set_height(kSize);
  lease.mutable_params()->set_frame(0);
  lease.add_inputs()->set_sha256("stage");
  lease.add_input_kinds(TASK_INTERPOLATE);
  lease.add_input_params()->set_frame(0);
  std::vector<uint8_t> mask(staged.pixelCount(), 0);
  FrameImage sparse(kSize, kSize);
  for (size_t t = 0; t < tiles.size(); ++t) {
    const PixelWindow& w = tiles[t].window;
    const FrameImage part = rendered.crop(w.x0(), w.y0(), w.x1() - w.x0(), w.y1() - w.y0());
    const std::string name = "tile" + std::to_string(t);
    chunks[name] = encodeExr(part, ExrCompression::Fast);
    lease.add_inputs()->set_sha256(name);
    lease.add_input_kinds(TASK_RENDER_TILE);
    TaskParams* params = lease.add_input_params();
    params->set_frame(0);
    *params->mutable_window() = w;
    params->set_pixel_mask(tiles[t].mask);
    sparse.paste(part, w.x0(), w.y0());
    for (int y = w.y0(); y < w.y1(); ++y)
      for (int x = w.x0(); x < w.x1(); ++x) {
        const size_t local = static_cast<size_t>((y - w.y0()) * 16 + (x - w.x0()));
        if (tiles[t].mask.empty() || tiles[t].mask[local]) mask[static_cast<size_t>(y * kSize + x)] = 1;
      }
  }
  sparse.attributes() = rendered.attributes();

  // The whole sparse frame, denoised at once: the directly seen light kept out, and every
  // pixel no tile rendered invalid.
  const FrameImage light = takeDirectEmission(sparse);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (const std::string& name : sparse.channelNames()) {
    const bool sampled = name == "R" || name == "G" || name == "B" || name.rfind("variance.", 0) == 0 ||
                         name.find(".color.") != std::string::npos ||
                         name.find(".irradiance.") != std::string::npos ||
                         name.find(".variance.") != std::string::npos;
    if (sampled)
      for (size_t p = 0; p < mask.size(); ++p)
        if (!mask[p]) sparse.channel(name)[p] = nan;
  }
  DenoiseSettings settings;
  settings.spatialRadius = 5;
  settings.fireflies.maxRadius = 8;  // the composite's short spread
  FrameImage expected = denoiseFrame(sparse, nullptr, nullptr, settings);
  ASSERT_NE(expected.attributes().at("pathfarm.denoise_fireflies"), "0");  // the spreads are compared too
  addDirectEmission(expected, light, &mask);

  TaskRunner runner(1, test_support::processTemporaryFolder("pathfarm_composite_scenes"),
                    test_support::processTemporaryFolder("pathfarm_composite_outgoing"));
  std::atomic<double> progress{0};
  std::atomic<bool> abandon{false};
  const FrameImage result = decodeExr(
      runner.run(lease, [&](const ChunkRef& ref) { return chunks.at(ref.sha256()); }, progress, abandon).chunk,
      "composite");
  size_t rerendered = 0;
  for (const std::string& name : {std::string("R"), std::string("G"), std::string("B"),
                                  std::string("diffuse_direct.color.G"), std::string("reflection.color.R")})
    for (size_t p = 0; p < mask.size(); ++p) {
      const float want = mask[p] ? expected.channel(name)[p] : staged.channel(name)[p];
      ASSERT_NEAR(result.channel(name)[p], want, 1e-5f * std::max(1.0f, std::abs(want))) << name << " pixel " << p;
      rerendered += mask[p];
    }
  EXPECT_EQ(result.attributes().at("pathfarm.rerender_pixels"), std::to_string(rerendered / 5));
  for (size_t p = 0; p < mask.size(); ++p) ASSERT_EQ(result.channel("rerender.Y")[p], mask[p]) << p;
}

TEST(CompositeTask, ATileWhosePixelMaskDoesNotFitItsWindowIsRefused) {
  FrameImage flat(4, 4);
  for (const char* c : {"R", "G", "B"}) flat.addChannel(c).assign(flat.pixelCount(), 0.5f);
  const std::map<std::string, std::string> chunks = {{"stage", encodeExr(flat, ExrCompression::Fast)},
                                                     {"tile", encodeExr(flat.crop(0, 0, 2, 2), ExrCompression::Fast)}};
  Lease lease;
  lease.set_kind(TASK_COMPOSITE);
  lease.mutable_spec()->set_width(4);
  lease.mutable_spec()->set_height(4);
  lease.mutable_params()->set_frame(0);
  lease.add_inputs()->set_sha256("stage");
  lease.add_input_kinds(TASK_UPSAMPLE);
  lease.add_input_params()->set_frame(0);
  lease.add_inputs()->set_sha256("tile");
  lease.add_input_kinds(TASK_RENDER_TILE);
  TaskParams* params = lease.add_input_params();
  params->set_frame(0);
  *params->mutable_window() = window(0, 0, 2, 2);
  params->set_pixel_mask(std::string(3, '\1'));
  TaskRunner runner(1, test_support::processTemporaryFolder("pathfarm_composite_scenes"),
                    test_support::processTemporaryFolder("pathfarm_composite_outgoing"));
  std::atomic<double> progress{0};
  std::atomic<bool> abandon{false};
  try {
    runner.run(lease, [&](const ChunkRef& ref) { return chunks.at(ref.sha256()); }, progress, abandon);
    FAIL() << "a pixel mask of the wrong size was read";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("has a pixel mask of 3 bytes for 4 pixels"), std::string::npos) << e.what();
  }
}

// A frame composited window by window, each window's task given only the re-render tiles
// within kCompositeHalo of its rows (as the scheduler gives them) and the windows joined,
// is the same bytes as the frame composited by one task; re-rendered content crosses both
// window borders.
TEST(CompositeTask, WindowsComposedApartAndJoinedAreTheWholeFramesBytes) {
  constexpr int kWidth = 40, kHeight = 120;
  const FrameImage staged = test_support::renderDecomposed("scenes/cornell/scene.json", kWidth, kHeight, 1, 0);
  const FrameImage rendered = test_support::renderDecomposed("scenes/cornell/scene.json", kWidth, kHeight, 16, 0);
  // Windows of rows 0-40, 40-80, 80-120; tiles across the first border, across the second
  // (in part, a diagonal), and one below the halo of the first window.
  std::vector<Tile> tiles = {{window(8, 32, 24, 48), ""}, {window(16, 72, 32, 88), std::string(256, '\0')},
                             {window(0, 100, 16, 116), ""}};
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x) tiles[1].mask[static_cast<size_t>(y * 16 + x)] = std::abs(x - y) < 4 ? 1 : 0;
  std::map<std::string, std::string> chunks = {{"stage", encodeExr(staged, ExrCompression::Fast)}};
  Lease whole;
  whole.set_kind(TASK_COMPOSITE);
  whole.mutable_spec()->set_pipeline(PIPELINE_DUI);
  whole.mutable_spec()->set_width(kWidth);
  whole.mutable_spec()->set_height(kHeight);
  whole.mutable_spec()->set_filter_window_rows(40);
  whole.mutable_params()->set_frame(0);
  const auto addInput = [](Lease& lease, const std::string& name, TaskKind kind, const TaskParams& params) {
    lease.add_inputs()->set_sha256(name);
    lease.add_input_kinds(kind);
    *lease.add_input_params() = params;
  };
  TaskParams stageParams;
  stageParams.set_frame(0);
  addInput(whole, "stage", TASK_INTERPOLATE, stageParams);
  std::vector<TaskParams> tileParams;
  for (size_t t = 0; t < tiles.size(); ++t) {
    const PixelWindow& w = tiles[t].window;
    chunks["tile" + std::to_string(t)] =
        encodeExr(rendered.crop(w.x0(), w.y0(), w.x1() - w.x0(), w.y1() - w.y0()), ExrCompression::Fast);
    TaskParams& params = tileParams.emplace_back();
    params.set_frame(0);
    *params.mutable_window() = w;
    params.set_pixel_mask(tiles[t].mask);
    addInput(whole, "tile" + std::to_string(t), TASK_RENDER_TILE, params);
  }
  TaskRunner runner(1, test_support::processTemporaryFolder("pathfarm_composite_scenes"),
                    test_support::processTemporaryFolder("pathfarm_composite_outgoing"));
  std::atomic<double> progress{0};
  std::atomic<bool> abandon{false};
  const auto run = [&](const Lease& lease) {
    return outputBytes(runner.run(lease, [&](const ChunkRef& ref) { return chunks.at(ref.sha256()); }, progress, abandon));
  };
  const std::string expected = run(whole);
  // A worker that keeps no frame decoded reads a window's rows of the stage from its file.
  const auto folder = test_support::processTemporaryFolder("pathfarm_composite_files");
  TaskRunner fromFiles(1, folder / "scenes", folder / "outgoing", 0);
  const auto runFromFiles = [&](const Lease& lease) {
    return outputBytes(fromFiles.run(
        lease, [](const ChunkRef&) -> std::string { throw std::logic_error("read in place"); }, progress, abandon,
        [&](const ChunkRef& ref) {
          const std::filesystem::path file = folder / (ref.sha256() + ".exr");
          if (!std::filesystem::exists(file)) std::ofstream(file, std::ios::binary) << chunks.at(ref.sha256());
          return file;
        }));
  };

  const std::vector<RowWindow> windows = filterWindowsOf(whole.spec());
  ASSERT_EQ(windows.size(), 3u);
  Lease join = whole;
  join.clear_inputs();
  join.clear_input_kinds();
  join.clear_input_params();
  const Lease noInputs = join;
  std::vector<size_t> tilesGiven;
  for (const RowWindow& rows : windows) {
    Lease part = noInputs;
    *part.mutable_params()->mutable_window() = window(0, rows.first, kWidth, rows.end);
    addInput(part, "stage", TASK_INTERPOLATE, stageParams);
    for (size_t t = 0; t < tiles.size(); ++t) {
      const PixelWindow& w = tiles[t].window;
      if (w.y1() <= rows.first - kCompositeHalo || w.y0() >= rows.end + kCompositeHalo) continue;
      addInput(part, "tile" + std::to_string(t), TASK_RENDER_TILE, tileParams[t]);
      tilesGiven.push_back(t);
    }
    const std::string name = "window" + std::to_string(rows.first);
    chunks[name] = run(part);
    EXPECT_TRUE(runFromFiles(part) == chunks[name]) << "rows " << rows.first << " read from the file";
    addInput(join, name, TASK_COMPOSITE, part.params());
  }
  EXPECT_EQ(tilesGiven, (std::vector<size_t>{0, 0, 1, 2, 1, 2})) << "the halo left no tile out";
  const std::string joined = run(join);
  EXPECT_TRUE(joined == expected) << "the joined windows differ from the whole frame's composite";
  EXPECT_TRUE(runFromFiles(join) == expected) << "joined from files";
  const FrameImage frame = decodeExr(joined, "joined");
  EXPECT_NE(frame.attributes().at("pathfarm.rerender_pixels"), "0");
  // Not the stage's pixels alone: the re-rendered ones at the borders are the denoised render.
  const size_t border = 40 * kWidth + 16;
  EXPECT_EQ(frame.channel("rerender.Y")[border], 1.0f);
  EXPECT_NE(frame.channel("R")[border], staged.channel("R")[border]);
}

}  // namespace
}  // namespace pathfarm::farm
