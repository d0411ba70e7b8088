#include "client/reference_cache.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdio>
#include <vector>

#include "client/scene_upload.h"
#include "proto/wire/sha256.h"
#include "renderer/integrators/frame_integrator.h"
#include "renderer/scene/scene_loader.h"
#include "renderer/setup/renderer_version.h"

namespace pathfarm::farm {

std::string referenceKey(const ShotSpec& described, int64_t frame, int rendererVersion) {
  // Everything a reference's pixels depend on, one fact a line; the inputs sorted, so the
  // order the scene loader read them in does not matter.
  std::vector<std::string> inputs;
  for (const InputFile& input : described.inputs()) inputs.push_back(input.path() + " " + input.chunk().sha256());
  std::sort(inputs.begin(), inputs.end());
  char settings[256];
  std::snprintf(settings, sizeof settings, "frame %lld\nsize %dx%d\nspp %d\nmax_depth %d\ncamera_zoom %.17g\n"
                "first_sample %u\n", static_cast<long long>(frame), described.width(), described.height(),
                described.reference_spp(), described.max_depth(), described.camera_zoom(), kIndependentFirstSample);
  std::string text = "pathfarm reference\nrenderer " + std::to_string(rendererVersion) + "\nscene " +
                     described.scene() + "\n";
  for (const std::string& input : inputs) text += "input " + input + "\n";
  std::string window;  // only for a window off the picture's centre, so that older keys stay valid
  if (described.camera_shift_x() != 0 || described.camera_shift_y() != 0) {
    char shift[96];
    std::snprintf(shift, sizeof shift, "camera_shift %.17g %.17g\n", described.camera_shift_x(),
                  described.camera_shift_y());
    window = shift;
  }
  return sha256Hex(text + settings + window);
}

std::map<int64_t, std::filesystem::path> ReferenceCache::filesOf(const ShotSpec& spec) const {
  ShotSpec described = spec;
  if (described.inputs().empty()) {  // a scene on shared storage: its files, named by digest
    try {
      describeSceneInputs(described);
    } catch (const SceneError& e) {
      spdlog::warn("references are not cached: {}", e.what());
      return {};
    }
  }
  std::map<int64_t, std::filesystem::path> files;
  for (const int64_t frame : spec.evaluation_frames())
    files[frame] = folder_ / (referenceKey(described, frame, kRendererVersion) + ".exr");
  return files;
}

int ReferenceCache::attach(FarmClient& client, ShotSpec& spec) const {
  if (spec.reference_spp() == 0) return 0;
  int attached = 0;
  for (const auto& [frame, file] : filesOf(spec)) {
    if (!std::filesystem::exists(file)) continue;
    const std::string bytes = readUploadFile(file);
    ChunkRef ref;
    ref.set_sha256(sha256Hex(bytes));
    ref.set_size(static_cast<int64_t>(bytes.size()));
    if (!client.missingInputs({ref}).empty()) client.putInput(bytes, ref);
    KnownReference* known = spec.add_known_references();
    known->set_frame(frame);
    *known->mutable_chunk() = ref;
    ++attached;
  }
  return attached;
}

int ReferenceCache::keep(FarmClient& client, int64_t shotId, const ShotSpec& spec) const {
  if (spec.reference_spp() == 0) return 0;
  const auto files = filesOf(spec);
  const auto lacking = std::count_if(files.begin(), files.end(),
                                     [](const auto& entry) { return !std::filesystem::exists(entry.second); });
  if (lacking == 0) return 0;
  std::filesystem::create_directories(folder_);
  // Every reference the farm sends is of an evaluation frame; one it gave is written again,
  // as the same bytes.
  client.fetchReferences(shotId, [&](int64_t frame) { return files.at(frame); });
  return static_cast<int>(lacking);
}

}  // namespace pathfarm::farm
