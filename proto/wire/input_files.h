#pragma once
// A shot's uploaded scene files (ShotSpec.inputs): the rules the client, the scheduler
// and every worker check alike — each path stays inside the scene's folder, each file once,
// the scene among them — and the digest that names the folder a worker rebuilds them in.
#include <string>

#include "pathfarm/shot.pb.h"

namespace pathfarm::farm {

// Relative, '/'-separated, no empty, "." or ".." part, no backslash or NUL, not too long.
bool isSafeInputPath(const std::string& path);
// Throws std::invalid_argument naming the first bad entry. A shot without inputs passes.
void checkInputFiles(const ShotSpec& spec);
// SHA-256 over the sorted (path, digest) list: shots with the same files share it.
std::string inputFilesDigest(const ShotSpec& spec);

}  // namespace pathfarm::farm
