// Light that reaches the camera without a diffuse vertex (the sky seen directly, in a
// mirror, through glass) survives every stage of the dui pipeline: each stage's output
// with a beauty has its components adding up to it, and the final frames show the sky
// where plain path tracing does. A deforming character (the creature scene) survives them the same way.
#include <cmath>
#include <map>
#include <set>

#include "farm/farm_fixture.h"
#include "image/exr_io.h"
#include "postproc/filters/decomposed_frame.h"
#include "proto/wire/chunk_store.h"

namespace pathfarm::farmtest {
namespace {

constexpr float kSky = 0.5f;

// A moving camera over a floor with a mirror sphere and a moving glass sphere, under a
// constant sky and a small lamp; the top rows of every frame see the sky.
fs::path writeSkyShot(const fs::path& folder, const std::string& pipeline) {
  writeFile(folder / "sky.json", R"({
    "camera": {"position": [0, 0.7, 4], "look_at": [0, 0.9, 0], "fov": 45, "shutter": [0, 0.5],
               "animation": {"translate": [{"frame": 0, "value": [-0.3, 0.7, 4]}, {"frame": 4, "value": [0.3, 0.7, 3.8]}]}},
    "materials": {"floor": {"type": "diffuse", "reflectance": 0.5},
                  "mirror": {"type": "conductor", "specular_color": 0.9},
                  "glass": {"type": "dielectric", "ior": 1.5},
                  "lamp": {"type": "diffuse", "reflectance": 0}},
    "environment": {"radiance": 0.5},
    "shapes": [
      {"type": "rectangle", "size": [6, 6], "material": "floor", "transform": {"rotate": {"axis": [1, 0, 0], "angle": -90}}},
      {"type": "sphere", "radius": 0.4, "material": "mirror", "transform": {"translate": [-0.5, 0.4, 0]}},
      {"type": "sphere", "radius": 0.35, "material": "glass",
       "animation": {"translate": [{"frame": 0, "value": [0.4, 0.35, 0.3]}, {"frame": 4, "value": [0.7, 0.35, 0.1]}]}},
      {"type": "rectangle", "size": [0.6, 0.6], "material": "lamp", "emission": 20,
       "transform": {"translate": [0, 3, 1], "rotate": {"axis": [1, 0, 0], "angle": 90}}}]
  })");
  const fs::path shot = folder / (pipeline + ".shot.json");
  writeFile(shot, R"({"name": "sky", "scene": "sky.json", "frames": {"start": 0, "end": 4}, "resolution": [64, 48],
    "spp": 8, "max_depth": 6, "pipeline": ")" + pipeline + R"(", "keyframe_interval": 2, "tile": 32,
    "baseline_core_seconds": 1})");
  return shot;
}

// The top rows see only the sky: exactly its radiance in every final frame.
void expectSkyInEveryFinalFrame(const fs::path& out) {
  for (int64_t frame = 0; frame <= 4; ++frame) {
    const FrameImage image = readExr(out / farm::frameFileName(frame));
    for (const char* c : {"R", "G", "B"})
      for (size_t p = 0; p < 2 * static_cast<size_t>(image.width()); ++p)
        ASSERT_NEAR(image.channel(c)[p], kSky, 1e-4) << "frame " << frame << ", channel " << c << ", pixel " << p;
  }
}

// The beauty equals the sum of the components' colors at every pixel, up to the rounding
// of each to a half float where an intermediate chunk stores them so (at most 2^-11 of
// each value).
void expectComponentsAddUp(const FrameImage& image, const std::string& label) {
  const std::vector<std::string> components = decompositionComponents(image);
  ASSERT_FALSE(components.empty()) << label;
  for (const char* c : {"R", "G", "B"}) {
    const std::vector<float>& beauty = image.channel(c);
    for (size_t p = 0; p < beauty.size(); ++p) {
      double sum = 0, magnitudes = std::abs(beauty[p]);
      for (const std::string& component : components) {
        sum += image.channel(component + ".color." + c)[p];
        magnitudes += std::abs(image.channel(component + ".color." + c)[p]);
      }
      ASSERT_NEAR(sum, beauty[p], 1e-4 * std::abs(beauty[p]) + std::exp2(-11.0) * magnitudes + 1e-5)
          << label << ", channel " << c << ", pixel " << p;
    }
  }
}

// Every finished output of the given kinds that holds components (baseline and reference
// renders are plain pt) has them adding up to its beauty; returns how many each kind had.
// The shots run with --keep-intermediates: by default each intermediate chunk leaves the
// store once read (docs/farm.md, "Retention").
std::map<int, int> expectEveryStageAddsUp(const fs::path& farmFolder, const std::set<int>& kinds) {
  const FarmDatabase db(farmFolder / "farm.db");
  const farm::ChunkStore store(farmFolder / "chunks");
  std::map<int, int> checked;  // task kind -> outputs checked
  for (const auto& row : db.rows("SELECT kind, output_sha FROM tasks WHERE state = 3")) {
    const int kind = std::stoi(row[0]);
    if (!kinds.contains(kind)) continue;
    const auto bytes = store.get(row[1]);
    EXPECT_TRUE(bytes) << "chunk " << row[1] << " is missing";
    if (!bytes) continue;
    const FrameImage image = decodeExr(*bytes, "chunk " + row[1]);
    // dui's half-resolution denoise output carries only what the upsampler reads, no beauty
    // (worker/chunk_channels.h): its light is checked in the upsampled keyframe.
    if (decompositionComponents(image).empty() || !image.hasChannel("R")) continue;
    expectComponentsAddUp(image, farm::TaskKind_Name(static_cast<farm::TaskKind>(kind)) + " " + row[1]);
    ++checked[kind];
  }
  return checked;
}

class SkyShotTest : public FarmTest {
 protected:
  // Runs the sky shot with `pipeline` on a local farm that is kept; returns its output folder.
  fs::path runSkyShot(const std::string& pipeline) {
    const fs::path out = dir() / (pipeline + "-out");
    const CommandResult local = runPathfarm({"local", writeSkyShot(dir(), pipeline).string(), "--workers", "2",
                                             "--threads", "1", "--out", out.string(), "--keep-farm",
                                             "--keep-intermediates"},
                                            {}, 300s);
    EXPECT_EQ(local.status, 0) << local.output;
    return out;
  }
};

TEST_F(SkyShotTest, SkyMirrorAndGlassLightSurviveEveryDuiStage) {
  const fs::path out = runSkyShot("dui");
  ASSERT_FALSE(HasFailure());
  const std::set<int> stages = {farm::TASK_ASSEMBLE_FRAME, farm::TASK_DENOISE,      farm::TASK_UPSAMPLE,
                                farm::TASK_INTERPOLATE,    farm::TASK_RENDER_TILE, farm::TASK_COMPOSITE};
  std::map<int, int> checked = expectEveryStageAddsUp(out / "farm", stages);
  for (const farm::TaskKind kind :
       {farm::TASK_ASSEMBLE_FRAME, farm::TASK_UPSAMPLE, farm::TASK_INTERPOLATE, farm::TASK_COMPOSITE})
    EXPECT_GT(checked[kind], 0) << "no output of " << farm::TaskKind_Name(kind) << " was checked";
  expectSkyInEveryFinalFrame(out);
}

// A character (the creature suite scene: a skinned tentacle and a morphing blob, mirrored
// and seen through glass) through every stage of dui: components still add up to the
// beauty, and every final frame is finite.
TEST_F(SkyShotTest, ADeformingCharacterSurvivesEveryDuiStage) {
  const fs::path shot = dir() / "creature.shot.json";
  writeFile(shot, R"({"name": "creature", "scene": ")" +
                      (fs::path(PATHFARM_SOURCE_DIR) / "scenes" / "creature" / "scene.json").string() +
                      R"(", "frames": {"start": 0, "end": 4}, "resolution": [64, 36], "spp": 4, "max_depth": 5,
    "pipeline": "dui", "keyframe_interval": 2, "tile": 32, "baseline_core_seconds": 1})");
  const fs::path out = dir() / "creature-out";
  const CommandResult local = runPathfarm(
      {"local", shot.string(), "--workers", "2", "--threads", "1", "--out", out.string(), "--keep-farm",
                                             "--keep-intermediates"}, {}, 300s);
  ASSERT_EQ(local.status, 0) << local.output;
  std::map<int, int> checked = expectEveryStageAddsUp(
      out / "farm", {farm::TASK_ASSEMBLE_FRAME, farm::TASK_DENOISE, farm::TASK_UPSAMPLE, farm::TASK_INTERPOLATE,
                     farm::TASK_RENDER_TILE, farm::TASK_COMPOSITE});
  for (const farm::TaskKind kind : {farm::TASK_UPSAMPLE, farm::TASK_INTERPOLATE})
    EXPECT_GT(checked[kind], 0) << "no output of " << farm::TaskKind_Name(kind) << " was checked";
  for (int64_t frame = 0; frame <= 4; ++frame) {
    const FrameImage image = readExr(out / farm::frameFileName(frame));
    for (const char* c : {"R", "G", "B"})
      for (const float v : image.channel(c)) ASSERT_TRUE(std::isfinite(v) && v >= 0) << "frame " << frame;
  }
}

// d writes its frames from the denoise tasks, without a composite: the sky must be
// there all the same.
TEST_F(SkyShotTest, SkyMirrorAndGlassLightSurviveTheDPipeline) {
  const fs::path out = runSkyShot("d");
  ASSERT_FALSE(HasFailure());
  std::map<int, int> checked = expectEveryStageAddsUp(
      out / "farm", {farm::TASK_ASSEMBLE_FRAME, farm::TASK_DENOISE, farm::TASK_COMPOSITE});
  EXPECT_EQ(checked[farm::TASK_DENOISE], 5);  // one final frame per frame
  EXPECT_EQ(checked[farm::TASK_COMPOSITE], 0);
  expectSkyInEveryFinalFrame(out);
}

}  // namespace
}  // namespace pathfarm::farmtest
