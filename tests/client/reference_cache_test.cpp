// The reference cache's key: it must change with everything a reference's pixels depend on
// (a scene file's bytes, the frame, the size, the samples, the depth, the renderer) and
// with nothing else (the order the scene's files were read in, the shot's own spp).
#include "client/reference_cache.h"

#include <gtest/gtest.h>

#include <functional>
#include <string>
#include <vector>

#include "client/shot_file.h"
#include "renderer/setup/renderer_version.h"
#include "test_support.h"

namespace pathfarm::farm {
namespace {

ShotSpec describedSpec() {
  ShotSpec spec;
  spec.set_scene("scene.json");
  for (const char* path : {"scene.json", "textures/wood.png", "meshes/chair.obj"}) {
    InputFile* input = spec.add_inputs();
    input->set_path(path);
    input->mutable_chunk()->set_sha256(std::string(64, path[0]));
  }
  spec.set_width(320);
  spec.set_height(180);
  spec.set_spp(64);
  spec.set_reference_spp(4096);
  spec.set_max_depth(8);
  return spec;
}

TEST(ReferenceKey, ChangesWithWhatTheReferenceDependsOnAndNothingElse) {
  const std::string key = referenceKey(describedSpec(), 11, kRendererVersion);
  EXPECT_EQ(key.size(), 64u);
  EXPECT_EQ(key, referenceKey(describedSpec(), 11, kRendererVersion)) << "a digest, the same every time";

  const std::vector<std::pair<const char*, std::function<void(ShotSpec&)>>> changes = {
      {"a texture's bytes", [](ShotSpec& s) { s.mutable_inputs(1)->mutable_chunk()->set_sha256(std::string(64, 'x')); }},
      {"a file's name", [](ShotSpec& s) { s.mutable_inputs(2)->set_path("meshes/table.obj"); }},
      {"one more file", [](ShotSpec& s) { s.add_inputs()->set_path("sky.exr"); }},
      {"the scene file", [](ShotSpec& s) { s.set_scene("meshes/chair.obj"); }},
      {"the width", [](ShotSpec& s) { s.set_width(321); }},
      {"the height", [](ShotSpec& s) { s.set_height(181); }},
      {"the reference's spp", [](ShotSpec& s) { s.set_reference_spp(4097); }},
      {"the depth", [](ShotSpec& s) { s.set_max_depth(9); }},
      {"the zoom", [](ShotSpec& s) { s.set_camera_zoom(2); }},
      {"the window's place across", [](ShotSpec& s) { s.set_camera_shift_x(0.25); }},
      {"the window's place down", [](ShotSpec& s) { s.set_camera_shift_y(-0.25); }},
  };
  for (const auto& [what, change] : changes) {
    ShotSpec changed = describedSpec();
    change(changed);
    EXPECT_NE(referenceKey(changed, 11, kRendererVersion), key) << what;
  }
  EXPECT_NE(referenceKey(describedSpec(), 12, kRendererVersion), key) << "another frame";
  EXPECT_NE(referenceKey(describedSpec(), 11, kRendererVersion + 1), key) << "another renderer version";

  ShotSpec reordered = describedSpec();
  reordered.mutable_inputs()->SwapElements(0, 2);
  EXPECT_EQ(referenceKey(reordered, 11, kRendererVersion), key) << "the order the files were read in";
  ShotSpec otherShot = describedSpec();
  otherShot.set_spp(256);
  otherShot.set_pipeline(PIPELINE_DUI);
  otherShot.set_name("another shot");
  EXPECT_EQ(referenceKey(otherShot, 11, kRendererVersion), key) << "what only the shot's own frames depend on";
}

// The demo's shots ship their references beside the scene, so that a fresh clone measures
// against 16384 spp without rendering them. A change to the scene or the renderer's version
// makes other keys: this fails until bench/demo_references.sh has rendered them anew.
TEST(ReferenceCache, TheDemosShippedReferencesAreTheOnesItsShotsAskFor) {
  for (const char* shot : {"cornell", "showroom"}) {
    const ShotFile file = ShotFile::load(test_support::sourceDir() / "scenes" / shot / "shot.json");
    ASSERT_FALSE(file.referenceCache().empty()) << shot;
    const auto files = ReferenceCache(file.referenceCache()).filesOf(file.spec());
    ASSERT_EQ(files.size(), static_cast<size_t>(file.spec().evaluation_frames_size())) << shot;
    for (const auto& [frame, path] : files)
      EXPECT_TRUE(std::filesystem::exists(path))
          << shot << ": no reference of frame " << frame << " (" << path.string()
          << "); run bench/demo_references.sh and commit what it writes";
  }
}

}  // namespace
}  // namespace pathfarm::farm
