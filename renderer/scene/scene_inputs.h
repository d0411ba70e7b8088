#pragma once
// The files a scene is made of: the scene file, its glTF include with buffers and images,
// meshes, textures and environment maps. Every reader of the scene loader notes the file
// it reads; a recorder collects them while it is alive, so that a client can ship a scene
// to workers that do not share its filesystem (client/scene_upload.h).
#include <filesystem>
#include <mutex>
#include <set>
#include <vector>

namespace pathfarm {

class SceneInputRecorder {
 public:
  // One recorder at a time: a second one waits for the first to end. Files read by any
  // thread while it lives are recorded.
  SceneInputRecorder();
  ~SceneInputRecorder();
  SceneInputRecorder(const SceneInputRecorder&) = delete;
  SceneInputRecorder& operator=(const SceneInputRecorder&) = delete;

  // Absolute, normalized, each once, in path order.
  std::vector<std::filesystem::path> files() const;

 private:
  std::unique_lock<std::mutex> active_;
};

// Called by the scene's readers with each file they read; does nothing unless a
// recorder is alive.
void noteSceneInput(const std::filesystem::path& file);

}  // namespace pathfarm
