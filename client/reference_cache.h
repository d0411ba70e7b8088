#pragma once
// References kept between shots. A reference is expensive (thousands of samples per pixel)
// and depends only on the scene's files, the frame, the resolution, its spp, the depth and
// the renderer, so it is kept in a folder under a key that digests all of them:
// KEY.exr. Before a shot is submitted, the references the folder holds for its evaluation
// frames are uploaded and named in the spec (ShotSpec.known_references), and the farm
// renders no reference for those frames; after it, the references the farm rendered join
// the folder. Any change to the scene, a texture, a setting or the renderer's version
// changes the key, so a stale reference is never used.
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>

#include "client/farm_client.h"
#include "pathfarm/shot.pb.h"

namespace pathfarm::farm {

// The key of the reference of `frame` for a spec whose inputs name the scene's files by
// digest (describeSceneInputs, uploadSceneInputs): 64 hex digits.
std::string referenceKey(const ShotSpec& described, int64_t frame, int rendererVersion);

class ReferenceCache {
 public:
  explicit ReferenceCache(std::filesystem::path folder) : folder_(std::move(folder)) {}

  // Uploads the references the folder holds for the spec's evaluation frames and names
  // them in `spec`; returns how many. A spec without reference_spp is left alone.
  int attach(FarmClient& client, ShotSpec& spec) const;
  // Fetches the references the farm rendered for shot `shotId` (submitted as `spec`) that
  // the folder lacks; returns how many it kept.
  int keep(FarmClient& client, int64_t shotId, const ShotSpec& spec) const;

  // Each evaluation frame's file in the folder (there or not); empty when the scene's files
  // cannot be named by content (then nothing is cached).
  std::map<int64_t, std::filesystem::path> filesOf(const ShotSpec& spec) const;
  const std::filesystem::path& folder() const { return folder_; }

 private:

  std::filesystem::path folder_;
};

}  // namespace pathfarm::farm
