#pragma once
// A frame, or a region of a large frame (scheduler/planner.cpp), assembled from its tiles'
// chunks and written to a file a strip of rows at a time: only the tiles crossing the
// strip being written are ever decoded at once, so a 16384 x 16384 frame needs no more
// memory than a row of its tiles.
// Nothing fetched is trusted: a tile of the wrong size or place, holding a non-finite
// value or not made by a pathfarm renderer is refused (BadInput), not pasted.
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>

#include "pathfarm/worker_service.pb.h"

namespace pathfarm::farm {

// The header needs every tile's attributes before the first row is written, so tiles are
// read twice: their headers, then their pixels. Tiles' compressed bytes up to this many
// are kept between the two readings instead of being fetched again.
inline constexpr uint64_t kKeptTileBytes = 256'000'000;

// Writes the frame the assemble_frame `lease` names to `file`; `fetch` returns a chunk's
// bytes. `progress` reaches 1 when the file is complete.
void assembleFrame(const Lease& lease, const std::function<std::string(const ChunkRef&)>& fetch,
                   const std::filesystem::path& file, std::atomic<double>& progress,
                   uint64_t keptTileBytes = kKeptTileBytes);

}  // namespace pathfarm::farm
