#include "renderer/scene/scene_inputs.h"

namespace pathfarm {
namespace {

std::mutex& recorderSlot() {
  static std::mutex slot;  // held by the live recorder
  return slot;
}

// The live recorder's files, or nothing; guarded by its own lock, as readers run on any thread.
struct Recording {
  std::mutex mutex;
  bool active = false;
  std::set<std::filesystem::path> files;
};

Recording& recording() {
  static Recording r;
  return r;
}

}  // namespace

SceneInputRecorder::SceneInputRecorder() : active_(recorderSlot()) {
  Recording& r = recording();
  const std::lock_guard lock(r.mutex);
  r.files.clear();
  r.active = true;
}

SceneInputRecorder::~SceneInputRecorder() {
  Recording& r = recording();
  const std::lock_guard lock(r.mutex);
  r.active = false;
  r.files.clear();
}

std::vector<std::filesystem::path> SceneInputRecorder::files() const {
  Recording& r = recording();
  const std::lock_guard lock(r.mutex);
  return {r.files.begin(), r.files.end()};
}

void noteSceneInput(const std::filesystem::path& file) {
  Recording& r = recording();
  const std::lock_guard lock(r.mutex);
  if (r.active) r.files.insert(std::filesystem::absolute(file).lexically_normal());
}

}  // namespace pathfarm
