#pragma once
// Small PNG pictures of a shot's output frames for the dashboard, made from the frames'
// EXR chunks on first request and kept by chunk digest (a chunk never changes, so a
// thumbnail never goes stale).
#include <deque>
#include <filesystem>
#include <map>
#include <mutex>
#include <string>

#include "image/frame_image.h"
#include "proto/wire/chunk_store.h"

namespace pathfarm::farm {

// The longest edge of a thumbnail, at most.
inline constexpr int kThumbnailEdge = 160;

// The beauty (R, G, B) of the EXR `file` shrunk by the smallest whole factor that fits
// both edges in `maxEdge`: each thumbnail pixel is the mean of its factor x factor block
// (fewer at the right and bottom edges). A frame that fits already comes out as it is. The
// file is read a strip of rows at a time. Throws ExrError naming `label`.
FrameImage shrinkBeauty(const std::filesystem::path& file, const std::string& label, int maxEdge = kThumbnailEdge);

class ThumbnailCache {
 public:
  explicit ThumbnailCache(const ChunkStore& store, size_t capacity = 2048) : store_(store), capacity_(capacity) {}

  // The PNG thumbnail of the frame in chunk `sha256`; throws ChunkError when the store
  // lacks the chunk and ExrError when it is not a frame.
  std::string png(const std::string& sha256);

 private:
  const ChunkStore& store_;
  size_t capacity_;
  std::mutex mutex_;
  std::map<std::string, std::string> pngs_;
  std::deque<std::string> insertionOrder_;  // the oldest goes first when full
};

}  // namespace pathfarm::farm
