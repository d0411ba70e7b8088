#pragma once
// The reference cache of `pathfarm local` and `pathfarm submit` (client/reference_cache.h):
// the folder --reference-cache names, else the shot file's "reference_cache", else none.
#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include <optional>
#include <string>

#include "client/reference_cache.h"
#include "client/shot_file.h"

namespace pathfarm {

inline void addReferenceCacheOption(CLI::App* command, std::string& folder) {
  command->add_option("--reference-cache", folder,
                      "folder keeping references between shots, by the digest of everything they depend on "
                      "(default: the shot file's \"reference_cache\", else none)");
}

inline std::optional<farm::ReferenceCache> referenceCacheOf(const farm::ShotFile& file, const std::string& option) {
  if (!option.empty()) return farm::ReferenceCache(option);
  if (!file.referenceCache().empty()) return farm::ReferenceCache(file.referenceCache());
  return std::nullopt;
}

inline void attachCachedReferences(const farm::ReferenceCache& cache, farm::FarmClient& client, farm::ShotSpec& spec) {
  if (spec.reference_spp() == 0) return;
  const int given = cache.attach(client, spec);
  spdlog::info("references: {} of {} evaluation frames from {}; the farm renders the rest", given,
               spec.evaluation_frames_size(), cache.folder().string());
}

inline void keepRenderedReferences(const farm::ReferenceCache& cache, farm::FarmClient& client, int64_t shotId,
                                   const farm::ShotSpec& spec) {
  if (const int kept = cache.keep(client, shotId, spec); kept > 0)
    spdlog::info("references: kept {} rendered by this shot in {}", kept, cache.folder().string());
}

}  // namespace pathfarm
