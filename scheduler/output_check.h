#pragma once
// What the scheduler checks of a task's output before accepting it: a worker, buggy or
// hostile, must not put into a shot a chunk that would spoil whatever reads it. Every
// image output must decode, hold only finite values and fit the shot's frame; a render
// tile or a region of a frame must have its window's size exactly.
#include <filesystem>
#include <string>

#include "pathfarm/shot.pb.h"

namespace pathfarm::farm {

// Why the output in `file` of a task of `kind` with `params` in the shot `spec` is refused;
// empty when it is sound. Outputs that are not images (no-op, evaluation) are not read.
// The file is read in place, a strip of rows at a time: a large frame is never whole in
// memory here.
std::string refusalOfOutput(const std::filesystem::path& file, TaskKind kind, const TaskParams& params,
                            const ShotSpec& spec);

}  // namespace pathfarm::farm
