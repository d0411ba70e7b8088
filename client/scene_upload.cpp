#include "client/scene_upload.h"

#include <fstream>
#include <set>
#include <sstream>

#include "proto/wire/connection.h"
#include "proto/wire/input_files.h"
#include "proto/wire/sha256.h"
#include "renderer/scene/json_node.h"
#include "renderer/scene/scene_inputs.h"
#include "renderer/scene/scene_loader.h"

namespace pathfarm::farm {
namespace {

namespace fs = std::filesystem;

bool isInside(const fs::path& file, const fs::path& folder) {
  const fs::path relative = file.lexically_relative(folder);
  return !relative.empty() && *relative.begin() != "..";
}

// The deepest folder holding every file.
fs::path commonFolder(const std::vector<fs::path>& files) {
  fs::path folder = files.front().parent_path();
  for (const fs::path& file : files) {
    while (!isInside(file, folder) && folder != folder.root_path()) folder = folder.parent_path();
  }
  return folder;
}

}  // namespace

std::string readUploadFile(const fs::path& file) {
  std::error_code error;
  const auto size = fs::file_size(file, error);
  if (error) throw SceneError(file.string() + ": cannot read the file (" + error.message() + ")");
  if (size > kMaxChunkBytes)
    throw SceneError(file.string() + ": larger than the farm's " + std::to_string(kMaxChunkBytes >> 30) +
                     " GiB limit per file");
  std::ifstream in(file, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  if (!in) throw SceneError(file.string() + ": cannot read the file");
  return bytes.str();
}

std::vector<fs::path> describeSceneInputs(ShotSpec& spec) {
  std::vector<fs::path> files;
  {
    const SceneInputRecorder recorder;
    loadScene(spec.scene());
    files = recorder.files();
  }
  const fs::path scene = fs::absolute(spec.scene()).lexically_normal();
  if (files.empty()) throw SceneError(scene.string() + ": loading the scene read no file");
  const fs::path root = commonFolder(files);

  spec.clear_inputs();
  for (const fs::path& file : files) {
    const std::string bytes = readUploadFile(file);
    InputFile* input = spec.add_inputs();
    input->set_path(file.lexically_relative(root).generic_string());
    input->mutable_chunk()->set_sha256(sha256Hex(bytes));
    input->mutable_chunk()->set_size(static_cast<int64_t>(bytes.size()));
  }
  spec.set_scene(scene.lexically_relative(root).generic_string());
  try {
    checkInputFiles(spec);
  } catch (const std::invalid_argument& e) {
    throw SceneError(scene.string() + ": " + e.what());
  }
  return files;
}

UploadSummary uploadSceneInputs(FarmClient& client, ShotSpec& spec) {
  const std::vector<fs::path> files = describeSceneInputs(spec);
  UploadSummary summary;
  std::vector<ChunkRef> chunks;
  for (const InputFile& input : spec.inputs()) {
    chunks.push_back(input.chunk());
    summary.bytes += static_cast<uint64_t>(input.chunk().size());
  }
  std::set<std::string> missing;
  for (const ChunkRef& ref : client.missingInputs(chunks)) missing.insert(ref.sha256());
  for (size_t i = 0; i < files.size(); ++i) {
    if (!missing.erase(chunks[i].sha256())) continue;  // stored already, or sent for an earlier file
    client.putInput(readUploadFile(files[i]), chunks[i]);
    ++summary.filesSent;
    summary.bytesSent += static_cast<uint64_t>(chunks[i].size());
  }
  summary.files = static_cast<int64_t>(files.size());
  return summary;
}

}  // namespace pathfarm::farm
