#include "worker/scene_files.h"

#include <unistd.h>

#include <atomic>
#include <fstream>

#include "proto/wire/input_files.h"

namespace pathfarm::farm {
namespace {

namespace fs = std::filesystem;

// Marks a folder whose every file was written.
constexpr const char* kCompleteMarker = ".complete";

void writeFile(const fs::path& file, const std::string& bytes) {
  fs::create_directories(file.parent_path());
  std::ofstream out(file, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  out.close();
  if (!out) throw std::runtime_error(file.string() + ": cannot write the scene file");
}

}  // namespace

fs::path localSceneFile(const ShotSpec& spec, const fs::path& scenesRoot, const TaskRunner::ChunkFetcher& fetch) {
  if (spec.inputs().empty()) {
    // A scene on shared storage this worker cannot see is the worker's problem (a missing
    // mount), not the scene's: the task should run elsewhere rather than fail the shot.
    if (!fs::exists(spec.scene()))
      throw std::runtime_error("this worker cannot see the scene file " + spec.scene() +
                               " (is the shared storage mounted here?)");
    return spec.scene();
  }
  checkInputFiles(spec);  // no path may leave the folder, whoever made the spec
  const fs::path folder = scenesRoot / inputFilesDigest(spec);
  if (fs::exists(folder / kCompleteMarker)) {
    std::error_code ignored;  // the last use, for the cache's trimming (worker/cache_trim.h)
    fs::last_write_time(folder, fs::file_time_type::clock::now(), ignored);
    return folder / spec.scene();
  }
  // Written aside and renamed into place: another slot or worker may build the same folder.
  static std::atomic<int> serial{0};
  const fs::path partial = scenesRoot / (folder.filename().string() + ".partial-" + std::to_string(getpid()) + "-" +
                                         std::to_string(serial++));
  fs::remove_all(partial);
  for (const InputFile& file : spec.inputs()) writeFile(partial / file.path(), fetch(file.chunk()));
  writeFile(partial / kCompleteMarker, "");
  std::error_code renamed;
  fs::rename(partial, folder, renamed);
  if (renamed) fs::remove_all(partial);  // someone else finished first; theirs is complete too
  if (!fs::exists(folder / kCompleteMarker))
    throw std::runtime_error(folder.string() + ": cannot rebuild the scene's files here (" + renamed.message() + ")");
  return folder / spec.scene();
}

}  // namespace pathfarm::farm
