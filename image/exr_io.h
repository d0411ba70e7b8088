#pragma once
// Multi-layer OpenEXR frames: every channel of a FrameImage as 32-bit float (or, where the
// writer asks, 16-bit), ZIP compressed (or RLE, for the farm's intermediate chunks),
// attributes as string header attributes. The same bytes go to files and
// over the wire (farm chunks). File writes are atomic (a temporary file, fsynced and
// renamed into place), so a reader never sees half a frame.
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "image/frame_image.h"

namespace pathfarm {

class ExrError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Small: ZIP, for frames people keep. Fast: RLE, for chunks a farm task writes for another
// to read: about 3x faster to write and 1.7x to read than ZIP, about 2x larger.
enum class ExrCompression { Small, Fast };

// Whether a channel, by its name, is wanted.
using ChannelFilter = std::function<bool(const std::string&)>;

// The channels `halfChannels` accepts are stored as 16-bit floats (OpenEXR's HALF), the
// others as 32-bit ones; readers get floats back either way. A half keeps 11 significant
// bits: a value of magnitude 2^-14 (6.1e-5) to 65504 comes back within 2^-11 of itself,
// relative, a smaller one within 2^-25, absolute. Only what fitsHalf accepts can be
// stored so: a half channel holding any other value is an ExrError.
std::string encodeExr(const FrameImage& frame, ExrCompression compression = ExrCompression::Small,
                      const ChannelFilter& halfChannels = {});
// Whether every value is finite and at most a half float's largest, 65504, in magnitude.
bool fitsHalf(const std::vector<float>& values);
// `label` names the bytes' origin (a file, a chunk) in error messages.
FrameImage decodeExr(const std::string& bytes, const std::string& label);
// decodeExr of a file's bytes, read in place: the file is never held in memory besides
// its frame (a 1080p keyframe chunk is about half a gigabyte). With `keep`, only the
// channels it accepts are decoded (every attribute is), so a task that reads one layer of
// a 150-channel frame holds that layer alone.
FrameImage decodeExrFile(const std::filesystem::path& file, const std::string& label, const ChannelFilter& keep = {});


// What checking a chunk finds without holding it: its size, and its first non-finite
// value ("channel C at pixel (x, y)", "" when every value is finite). The file is read in
// place, `rowsPerStrip` rows at a time, after the same header checks as decodeExr's (on
// the file's first 16 MiB: headers beyond that are refused). Throws ExrError naming
// `label`, as decodeExr does.
struct ExrScan {
  int width = 0, height = 0;
  std::string firstNonFinite;
};
ExrScan scanExrFile(const std::filesystem::path& file, const std::string& label, int rowsPerStrip = 16);

// Rows firstRow .. firstRow + rows - 1 (from the top) of a width x height data window, of
// the channels in `names`: one plane of width x rows floats each, valid during the call.
struct ExrStrip {
  int width = 0, height = 0, firstRow = 0, rows = 0;
  std::span<const std::string> names;
  std::span<float* const> planes;
};
// Reads a file in place a strip of `rowsPerStrip` rows at a time, with scanExrFile's
// checks, handing each strip of `channels` (every channel when empty) to `strip` until it
// returns false. Returns the data window's width and height. A channel the file lacks, or
// one named twice, is an ExrError naming `label`, as is everything scanExrFile refuses.
std::pair<int, int> readExrStrips(const std::filesystem::path& file, const std::string& label,
                                  const std::vector<std::string>& channels, int rowsPerStrip,
                                  const std::function<bool(const ExrStrip&)>& strip);

// What a file's header says, read without its pixels (with scanExrFile's checks).
struct ExrHeader {
  int width = 0, height = 0;
  std::vector<std::string> channels;              // in the file's (alphabetical) order
  std::map<std::string, std::string> attributes;  // its string attributes
  std::vector<std::string> halfChannels;          // those of `channels` stored as 16-bit floats
};
ExrHeader readExrHeader(const std::filesystem::path& file, const std::string& label);
// The same of an EXR's bytes.
ExrHeader decodeExrHeader(const std::string& bytes, const std::string& label);
// Rows from .. to - 1 (from the top) of every channel of a file (of those `keep` accepts,
// with it), with its attributes, read in place (with scanExrFile's checks): a part of a
// frame too large to hold.
FrameImage readExrRows(const std::filesystem::path& file, const std::string& label, int from, int to,
                       const ChannelFilter& keep = {});

void writeExr(const std::filesystem::path& file, const FrameImage& frame);

// Writes an EXR file a strip of rows at a time, top to bottom, so that a frame larger than
// memory can be written from its parts. The bytes equal encodeExr's of the whole frame.
class ExrStripWriter {
 public:
  // Throws ExrError when the file cannot be created.
  ExrStripWriter(const std::filesystem::path& file, int width, int height, const std::vector<std::string>& channels,
                 const std::map<std::string, std::string>& attributes, ExrCompression compression,
                 const ChannelFilter& halfChannels = {});
  ~ExrStripWriter();
  // The next strip.height() rows: `strip` has the file's width and all of its channels.
  // Throws ExrError otherwise, or for rows past the frame's height.
  void write(const FrameImage& strip);
  int rowsWritten() const { return rows_; }
  // Closes the file; throws ExrError unless every row was written.
  void finish();

 private:
  struct Output;
  std::unique_ptr<Output> out_;
  std::filesystem::path file_;
  int width_, height_, rows_ = 0;
  std::vector<std::string> channels_;
  ChannelFilter half_;
};
// Writes a frame held in memory to `file` a strip of rows at a time (ExrStripWriter): the
// bytes of encodeExr, never held in memory beside the frame.
void writeExrInStrips(const std::filesystem::path& file, const FrameImage& frame, ExrCompression compression,
                      const ChannelFilter& halfChannels = {});

// A missing, truncated or corrupted file throws ExrError naming the file.
FrameImage readExr(const std::filesystem::path& file);

}  // namespace pathfarm
