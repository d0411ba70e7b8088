#pragma once
// Rows of float (and half) channels decoded with OpenEXRCore, OpenEXR's C library. OpenEXR 3.1's
// Imf::InputFile converts every value of a chunk through a reader of one byte at a time;
// the C library unpacks the farm's RLE and ZIP chunks faster, to the same bits
// (docs/performance.md, "Chunks decoded by OpenEXRCore"). exr_io.cpp reads every frame's
// pixels here when it can, and with Imf::InputFile otherwise.
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace pathfarm {

// An EXR held in memory, or a file (when `file` is set).
struct ExrBytes {
  std::string_view bytes;
  const std::filesystem::path* file = nullptr;
};

// Rows of the channels `names` of one EXR, decoded a range at a time.
class ExrCoreRows {
 public:
  // Opens the EXR; usable() is false when it is not what this reader handles: one part of
  // scan lines, uncompressed or packed by RLE or ZIP, whose named channels are all FLOAT
  // or HALF (unpacked into floats) and sampled at every pixel. Throws
  // std::runtime_error with OpenEXRCore's message when its bytes are damaged, or when it
  // lacks a named channel. Its header was checked and parsed by Imf::InputFile before
  // (exr_io.cpp).
  ExrCoreRows(const ExrBytes& source, const std::vector<std::string>& names);
  ~ExrCoreRows();
  ExrCoreRows(const ExrCoreRows&) = delete;
  ExrCoreRows& operator=(const ExrCoreRows&) = delete;

  bool usable() const { return usable_; }
  // Decodes rows [from, to) of the data window (0: its first row) into `planes`, one per
  // name, each the data window's width times to - from floats.
  void read(const std::vector<float*>& planes, int from, int to);

 private:
  struct Reader;
  std::unique_ptr<Reader> reader_;
  bool usable_ = false;
};

}  // namespace pathfarm
