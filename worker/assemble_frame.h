#pragma once
// A frame, or a region of a large frame (scheduler/planner.cpp), assembled from its tiles'
// chunks and written to a file a strip of rows at a time. Tiles are read in place from
// their files, only the rows of the strip being written: a 16384 x 16384 frame needs
// memory for one strip, not for the frame, its regions or its encoded bytes.
// Nothing fetched is trusted: a tile of the wrong size or place, holding a non-finite
// value or not made by a pathfarm renderer is refused (BadInput), not pasted.
#include <atomic>
#include <filesystem>
#include <functional>

#include "pathfarm/worker_service.pb.h"

namespace pathfarm::farm {

// A chunk as a file whose bytes were verified, which stays in place while the task runs.
using ChunkFileFetcher = std::function<std::filesystem::path(const ChunkRef&)>;

// Writes the frame the assemble_frame `lease` names to `file`. `progress` reaches 1 when
// the file is complete.
void assembleFrame(const Lease& lease, const ChunkFileFetcher& fetch, const std::filesystem::path& file,
                   std::atomic<double>& progress);

}  // namespace pathfarm::farm
