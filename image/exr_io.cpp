#include "image/exr_io.h"

#include "image/atomic_file.h"
#include "image/exr_core_rows.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStdIO.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <Imath/half.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <functional>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <tuple>
#include <utility>
#include <vector>

namespace pathfarm {

namespace {

Imf::Header headerOf(int width, int height, const std::vector<std::string>& channels,
                     const std::map<std::string, std::string>& attributes, ExrCompression compression,
                     const ChannelFilter& half) {
  Imf::Header header(width, height);
  header.compression() = compression == ExrCompression::Small ? Imf::ZIP_COMPRESSION : Imf::RLE_COMPRESSION;
  for (const auto& [name, value] : attributes) header.insert(name, Imf::StringAttribute(value));
  for (const std::string& name : channels)
    header.channels().insert(name, Imf::Channel(half && half(name) ? Imf::HALF : Imf::FLOAT));
  return header;
}

// Whether a half float holds `value` (to within its precision): NaNs and infinities fail.
bool halfHolds(float value) { return std::abs(value) <= HALF_MAX; }

// What OpenEXR writes rows firstRow .. firstRow + rows - 1 of a frame `width` wide from:
// a float channel's plane (holding those rows from its start) itself, a half channel's
// rows converted into a buffer of their own, kept here until the rows are written.
class RowsToWrite {
 public:
  RowsToWrite(int width, const std::vector<std::string>& names, const std::vector<const float*>& planes,
              int firstRow, int rows, const ChannelFilter& half) {
    const auto count = static_cast<size_t>(width) * static_cast<size_t>(rows);
    for (size_t c = 0; c < names.size(); ++c) {
      const bool isHalf = half && half(names[c]);
      // OpenEXR addresses slices by absolute pixel coordinates: the base is shifted back to
      // row 0. Its Slice takes a non-const pointer but only reads when writing.
      const size_t pixelBytes = isHalf ? sizeof(Imath::half) : sizeof(float);
      char* rowsStart = reinterpret_cast<char*>(const_cast<float*>(planes[c]));
      if (isHalf) rowsStart = reinterpret_cast<char*>(halved(names[c], planes[c], count));
      const size_t rowBytes = pixelBytes * static_cast<size_t>(width);
      buffer_.insert(names[c], Imf::Slice(isHalf ? Imf::HALF : Imf::FLOAT,
                                          rowsStart - static_cast<ptrdiff_t>(firstRow) * static_cast<ptrdiff_t>(rowBytes),
                                          pixelBytes, rowBytes));
    }
  }
  const Imf::FrameBuffer& buffer() const { return buffer_; }

 private:
  Imath::half* halved(const std::string& name, const float* values, size_t count) {
    std::vector<Imath::half>& converted = halves_.emplace_back(count);
    for (size_t i = 0; i < count; ++i) {
      if (!halfHolds(values[i]))
        throw std::range_error("channel \"" + name + "\" holds " + std::to_string(values[i]) +
                               ", which a 16-bit float cannot store");
      converted[i] = Imath::half(values[i]);
    }
    return converted.data();
  }

  std::vector<std::vector<Imath::half>> halves_;
  Imf::FrameBuffer buffer_;
};

std::vector<const float*> planesOf(const FrameImage& frame, const std::vector<std::string>& names) {
  std::vector<const float*> planes;
  for (const std::string& name : names) planes.push_back(frame.channel(name).data());
  return planes;
}

// OpenEXR's output into a string that grows in place, reserved for the frame's raw size up
// front (pages not written are never touched): Imf::StdOSStream would hold the bytes
// twice, in its buffer grown by doubling and in the copy str() returns, which for a 1080p
// filtered keyframe was gigabytes on top of the frame.
class StringOStream : public Imf::OStream {
 public:
  explicit StringOStream(size_t expected) : Imf::OStream("memory") { bytes_.reserve(expected); }

  void write(const char c[], int n) override {
    const size_t end = position_ + static_cast<size_t>(n);
    if (end > bytes_.size()) bytes_.resize(end);
    std::memcpy(bytes_.data() + position_, c, static_cast<size_t>(n));
    position_ = end;
  }
  uint64_t tellp() override { return position_; }
  void seekp(uint64_t position) override { position_ = position; }
  std::string take() { return std::move(bytes_); }

 private:
  std::string bytes_;
  size_t position_ = 0;
};

// OpenEXR's input from bytes held elsewhere, read in place (Imf::StdISStream copies them).
class StringIStream : public Imf::IStream {
 public:
  explicit StringIStream(std::string_view bytes) : Imf::IStream("memory"), bytes_(bytes) {}

  bool read(char c[], int n) override {
    if (n < 0 || position_ > bytes_.size() || static_cast<size_t>(n) > bytes_.size() - position_)
      throw std::runtime_error("unexpected end of the EXR bytes");
    std::memcpy(c, bytes_.data() + position_, static_cast<size_t>(n));
    position_ += static_cast<size_t>(n);
    return position_ < bytes_.size();
  }
  uint64_t tellg() override { return position_; }
  void seekg(uint64_t position) override { position_ = position; }

 private:
  std::string_view bytes_;
  size_t position_ = 0;
};

}  // namespace

bool fitsHalf(const std::vector<float>& values) {
  return std::all_of(values.begin(), values.end(), halfHolds);
}

std::string encodeExr(const FrameImage& frame, ExrCompression compression, const ChannelFilter& halfChannels) {
  try {
    const Imf::Header header =
        headerOf(frame.width(), frame.height(), frame.channelNames(), frame.attributes(), compression, halfChannels);
    const RowsToWrite rows(frame.width(), frame.channelNames(), planesOf(frame, frame.channelNames()), 0,
                           frame.height(), halfChannels);
    // Room for the raw planes, the line offsets and the header: RLE and ZIP store a block
    // raw where packing would enlarge it.
    StringOStream stream(frame.pixelCount() * frame.channelNames().size() * sizeof(float) +
                         static_cast<size_t>(frame.height()) * 16 + (size_t{1} << 20));
    {
      Imf::OutputFile out(stream, header);  // finishes the file when it goes out of scope
      out.setFrameBuffer(rows.buffer());
      out.writePixels(frame.height());
    }
    return stream.take();
  } catch (const std::exception& e) {
    throw ExrError(std::string("cannot encode EXR: ") + e.what());
  }
}

namespace {

// A damaged chunk (or a hostile file) can claim a data window of billions of pixels in a
// header of a few bytes; decoding it would allocate gigabytes before OpenEXR found the
// pixels missing. So a frame whose float planes would need more bytes than its compression
// can unpack from the bytes it came in is refused before anything is allocated. zlib packs
// at most 1032:1, and no other lossless EXR compression packs tighter; PXR24 adds 4/3 and
// half channels double as floats: 4096. DWA keeps one coefficient of a flat 8x8 block
// before zlib: 64 times more.
constexpr uint64_t kMaxExpansion = 4096;
constexpr uint64_t kMaxDwaExpansion = 64 * kMaxExpansion;
constexpr int kDwaaCompression = 8, kDwabCompression = 9;  // OpenEXR's file format numbers
// scanExrFile walks at most this much of a file's start for its headers: a frame's
// headers take kilobytes.
constexpr size_t kMaxScannedHeaderBytes = size_t{16} << 20;

// What decodeExr needs to know of the first header before OpenEXR reads it.
struct HeaderSummary {
  // A header without a data window keeps OpenEXR's default one, 64 x 64 pixels.
  int64_t width = 64, height = 64;
  size_t channels = 0;
  int compression = 0;
  int64_t tileWidth = 0, tileHeight = 0;  // a tiled file's tile size (0: scan lines)
};

int32_t readInt32(std::string_view bytes, size_t pos) {
  if (bytes.size() < 4 || pos > bytes.size() - 4) throw std::runtime_error("truncated header");
  uint32_t value = 0;
  for (int i = 3; i >= 0; --i) value = value << 8 | static_cast<unsigned char>(bytes[pos + static_cast<size_t>(i)]);
  return static_cast<int32_t>(value);
}

// A NUL-terminated name at `pos`, which moves past it. Attribute and type names are at
// most 31 bytes, or 255 in files flagged for long names, channel names at most 255:
// OpenEXR reads no further.
std::string_view readName(std::string_view bytes, size_t& pos, size_t maxLength) {
  const size_t end = bytes.find('\0', pos);
  if (end == std::string_view::npos) throw std::runtime_error("truncated header");
  const std::string_view name = bytes.substr(pos, end - pos);
  if (name.size() > maxLength) throw std::runtime_error("a header name is longer than " + std::to_string(maxLength) + " bytes");
  pos = end + 1;
  return name;
}

// The bytes a value of each fixed-size attribute type of OpenEXR 3.1 takes.
size_t fixedSizeOf(std::string_view type) {
  static constexpr std::pair<std::string_view, size_t> kSizes[] = {
      {"box2i", 16},   {"box2f", 16}, {"chromaticities", 32}, {"compression", 1}, {"deepImageState", 1},
      {"double", 8},   {"envmap", 1}, {"float", 4},           {"int", 4},         {"keycode", 28},
      {"lineOrder", 1}, {"m33f", 36}, {"m33d", 72},           {"m44f", 64},       {"m44d", 128},
      {"rational", 8}, {"tiledesc", 9}, {"timecode", 8},      {"v2i", 8},         {"v2f", 8},
      {"v2d", 16},     {"v3i", 12},   {"v3f", 12},            {"v3d", 24}};
  for (const auto& [name, size] : kSizes)
    if (name == type) return size;
  return 0;
}

// OpenEXR reads a value of a known type by the type's own layout and the next attribute
// from where that stopped, but allocates what the declared size (or a preview's width and
// height, a string vector's lengths) asks before reading. A value must take exactly its
// declared size, so that this walk and OpenEXR's agree on where every attribute is.
// Returns the number of channels of a channel list.
size_t checkAttributeValue(std::string_view name, std::string_view type, std::string_view value) {
  const auto damaged = [&](const std::string& what) {
    throw std::runtime_error("header attribute \"" + std::string(name) + "\" (" + std::string(type) + "): " + what);
  };
  size_t channels = 0;
  if (const size_t fixed = fixedSizeOf(type)) {
    if (value.size() != fixed)
      damaged(std::to_string(value.size()) + " bytes where the type has " + std::to_string(fixed));
  } else if (type == "chlist") {
    // Each channel: its name, then 16 bytes (type, pLinear, reserved, sampling); an empty name ends the list.
    size_t at = 0;
    for (size_t end = value.find('\0'); end != at; end = value.find('\0', at)) {
      if (end == std::string_view::npos || value.size() - (end + 1) < 16) damaged("the list runs past its declared size");
      if (end - at > 255) damaged("a channel name is longer than 255 bytes");
      at = end + 1 + 16;
      ++channels;
    }
    if (at + 1 != value.size()) damaged("the list ends before its declared size");
  } else if (type == "preview") {
    if (value.size() < 8) damaged("no width and height");
    const uint64_t width = static_cast<uint32_t>(readInt32(value, 0));
    const uint64_t height = static_cast<uint32_t>(readInt32(value, 4));
    if (width != 0 && (height > (value.size() - 8) / 4 / width || 4 * width * height != value.size() - 8))
      damaged("a " + std::to_string(width) + " x " + std::to_string(height) + " preview in " +
              std::to_string(value.size()) + " bytes");
  } else if (type == "stringvector") {
    for (size_t at = 0; at < value.size();) {
      const int32_t length = readInt32(value, at);
      at += 4;
      if (length < 0 || static_cast<size_t>(length) > value.size() - at)
        damaged("a string of " + std::to_string(length) + " bytes where " + std::to_string(value.size() - at) +
                " remain");
      at += static_cast<size_t>(length);
    }
  }
  return channels;
}

// Walks the headers (OpenEXR's file layout: magic, version, then per part attributes as
// name, type, size, value until an empty name) before OpenEXR does, which allocates the
// size an attribute claims before reading it: up to 2 GB for a few damaged bytes.
HeaderSummary readHeaders(std::string_view bytes) {
  if (!bytes.starts_with("\x76\x2f\x31\x01")) throw std::runtime_error("not an OpenEXR file (bad magic number)");
  const int32_t flags = readInt32(bytes, 4);
  const bool multipart = (flags & 0x1000) != 0;
  const size_t maxName = (flags & 0x400) != 0 ? 255 : 31;
  HeaderSummary summary;
  size_t pos = 8;
  for (bool first = true;; first = false) {
    bool empty = true;
    for (std::string_view name = readName(bytes, pos, maxName); !name.empty(); name = readName(bytes, pos, maxName)) {
      empty = false;
      const std::string_view type = readName(bytes, pos, maxName);
      const int32_t size = readInt32(bytes, pos);
      pos += 4;
      if (size < 0 || static_cast<size_t>(size) > bytes.size() - pos)
        throw std::runtime_error("header attribute \"" + std::string(name) + "\" claims " + std::to_string(size) +
                                 " bytes, but " + std::to_string(bytes.size() - pos) + " follow");
      const std::string_view value = bytes.substr(pos, static_cast<size_t>(size));
      const size_t channels = checkAttributeValue(name, type, value);
      if (first && name == "dataWindow" && type == "box2i") {
        summary.width = int64_t{readInt32(value, 8)} - readInt32(value, 0) + 1;
        summary.height = int64_t{readInt32(value, 12)} - readInt32(value, 4) + 1;
      }
      if (first && name == "compression" && type == "compression") summary.compression = static_cast<unsigned char>(value[0]);
      if (first && name == "channels" && type == "chlist") summary.channels = channels;
      if (first && name == "tiles" && type == "tiledesc") {
        summary.tileWidth = static_cast<uint32_t>(readInt32(value, 0));
        summary.tileHeight = static_cast<uint32_t>(readInt32(value, 4));
      }
      pos += static_cast<size_t>(size);
    }
    if (!multipart || empty) return summary;
  }
}

void refuseImplausibleSize(const HeaderSummary& header, size_t bytes) {
  if (header.width < 1 || header.height < 1) throw std::length_error("empty data window");
  const bool dwa = header.compression == kDwaaCompression || header.compression == kDwabCompression;
  const uint64_t expansion = dwa ? kMaxDwaExpansion : kMaxExpansion;
  const uint64_t limit = expansion * static_cast<uint64_t>(bytes);
  const uint64_t perPixel = sizeof(float) * std::max<uint64_t>(header.channels, 1);
  const auto refuse = [&](const std::string& what) {
    throw std::length_error(what + " and " + std::to_string(header.channels) + " channels cannot come from " +
                            std::to_string(bytes) + " bytes (its compression packs at most " + std::to_string(expansion) +
                            " times)");
  };
  if (static_cast<uint64_t>(header.width) * static_cast<uint64_t>(header.height) > limit / perPixel)
    refuse("a data window of " + std::to_string(header.width) + " x " + std::to_string(header.height) + " pixels");
  // OpenEXR buffers a whole row of tiles of the size the header declares, whatever the
  // data window: a row of tiles must be as plausible as the window itself.
  if (header.tileWidth > 0 && header.tileHeight > 0) {
    const uint64_t tilesAcross = (static_cast<uint64_t>(header.width) + header.tileWidth - 1) / header.tileWidth;
    const uint64_t rowWidth = tilesAcross * static_cast<uint64_t>(header.tileWidth);
    if (rowWidth > limit / perPixel || static_cast<uint64_t>(header.tileHeight) > limit / perPixel / rowWidth)
      refuse("a row of " + std::to_string(header.tileWidth) + " x " + std::to_string(header.tileHeight) +
             " pixel tiles " + std::to_string(rowWidth) + " pixels wide");
  }
}

// A frame buffer of `planes`, one per channel in `names`, holding rows firstRow,
// firstRow + 1, ... of the data window, its width in floats each. OpenEXR addresses slices
// by absolute pixel coordinates: the base pointer is shifted so the window's column min.x
// of row firstRow lands on the plane's first element.
Imf::FrameBuffer frameBufferOf(const Imath::Box2i& window, const std::vector<std::string>& names,
                               const std::vector<float*>& planes, int firstRow) {
  const size_t rowStride = sizeof(float) * static_cast<size_t>(window.max.x - window.min.x + 1);
  Imf::FrameBuffer buffer;
  for (size_t c = 0; c < names.size(); ++c) {
    char* base = reinterpret_cast<char*>(planes[c]) -
                 static_cast<ptrdiff_t>(window.min.x) * static_cast<ptrdiff_t>(sizeof(float)) -
                 static_cast<ptrdiff_t>(firstRow) * static_cast<ptrdiff_t>(rowStride);
    buffer.insert(names[c], Imf::Slice(Imf::FLOAT, base, sizeof(float), rowStride));
  }
  return buffer;
}

std::vector<std::string> channelNames(const Imf::Header& header) {
  std::vector<std::string> names;
  for (auto it = header.channels().begin(); it != header.channels().end(); ++it) names.emplace_back(it.name());
  return names;
}

std::map<std::string, std::string> stringAttributes(const Imf::Header& header) {
  std::map<std::string, std::string> attributes;
  for (auto it = header.begin(); it != header.end(); ++it) {
    if (const auto* s = dynamic_cast<const Imf::StringAttribute*>(&it.attribute())) attributes[it.name()] = s->value();
  }
  return attributes;
}

// Runs `read` on an OpenEXR reader of `stream`, and where its bytes are, once its
// headers, the first bytes of the `total` it holds, passed readHeaders' checks.
template <class Read>
auto readChecked(std::string_view headers, size_t total, Imf::IStream& stream, const ExrBytes& source, Read read) {
  refuseImplausibleSize(readHeaders(headers), total);
  Imf::InputFile in(stream);
  return read(in, source);
}

// Hands `strip` the rows of `names` a strip at a time, until it returns false.
std::pair<int, int> readStrips(Imf::InputFile& in, const ExrBytes& source, const std::vector<std::string>& names,
                               int rowsPerStrip, const std::function<bool(const ExrStrip&)>& strip) {
  const Imath::Box2i window = in.header().dataWindow();
  const int width = window.max.x - window.min.x + 1, height = window.max.y - window.min.y + 1;
  for (const std::string& name : names)
    if (in.header().channels().findChannel(name) == nullptr) throw std::runtime_error("no channel \"" + name + "\"");
  // A frame buffer holds one plane a channel: a name asked twice would leave a plane unread.
  for (size_t i = 0; i < names.size(); ++i)
    if (std::find(names.begin(), names.begin() + static_cast<ptrdiff_t>(i), names[i]) != names.begin() + static_cast<ptrdiff_t>(i))
      throw std::runtime_error("channel \"" + names[i] + "\" asked for twice");
  const int rows = std::clamp(rowsPerStrip, 1, height);
  std::vector<std::vector<float>> planes(names.size(), std::vector<float>(static_cast<size_t>(width) * rows));
  std::vector<float*> pointers;
  for (std::vector<float>& plane : planes) pointers.push_back(plane.data());
  ExrStrip part{width, height, 0, 0, names, {pointers.begin(), pointers.end()}};
  ExrCoreRows core(source, names);
  for (int y0 = window.min.y; y0 <= window.max.y; y0 += rows) {
    const int y1 = std::min(window.max.y, y0 + rows - 1);
    if (core.usable()) {
      core.read(pointers, y0 - window.min.y, y1 + 1 - window.min.y);
    } else {
      in.setFrameBuffer(frameBufferOf(window, names, pointers, y0));
      in.readPixels(y0, y1);
    }
    part.firstRow = y0 - window.min.y;
    part.rows = y1 - y0 + 1;
    if (!strip(part)) break;
  }
  return {width, height};
}

// Runs `read` on an OpenEXR reader of `bytes`; any failure is an ExrError naming `label`.
template <class Read>
auto readBytes(const std::string& bytes, const std::string& label, Read read) {
  try {
    StringIStream stream(bytes);
    return readChecked(bytes, bytes.size(), stream, ExrBytes{bytes}, read);
  } catch (const std::exception& e) {
    throw ExrError(label + ": cannot read EXR: " + e.what());
  }
}

// Runs `read` on an OpenEXR reader of the file, read in place once its headers (in its
// first kMaxScannedHeaderBytes) passed readHeaders' checks; any failure is an ExrError
// naming `label`.
template <class Read>
auto readFile(const std::filesystem::path& file, const std::string& label, Read read) {
  try {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw std::runtime_error("no such file or not readable");
    const auto total = static_cast<size_t>(std::filesystem::file_size(file));
    std::string headers(std::min(total, kMaxScannedHeaderBytes), '\0');
    in.read(headers.data(), static_cast<std::streamsize>(headers.size()));
    in.seekg(0);
    Imf::StdIFStream stream(in, file.c_str());
    return readChecked(headers, total, stream, ExrBytes{{}, &file}, read);
  } catch (const std::exception& e) {
    throw ExrError(label + ": cannot read EXR: " + e.what());
  }
}

}  // namespace

namespace {

// Rows from .. to - 1 (every row when `to` is negative) of the channels `keep` accepts
// (every one without it), with every attribute of the reader's frame.
FrameImage framePart(Imf::InputFile& in, const ExrBytes& source, const ChannelFilter& keep, int from = 0,
                     int to = -1) {
  const Imath::Box2i window = in.header().dataWindow();
  const int height = window.max.y - window.min.y + 1;
  if (to < 0) to = height;
  if (from < 0 || to > height || from >= to)
    throw std::runtime_error("rows " + std::to_string(from) + " to " + std::to_string(to) + " of a frame of " +
                             std::to_string(height) + " rows");
  FrameImage frame(window.max.x - window.min.x + 1, to - from);
  std::vector<std::string> names = channelNames(in.header());
  if (keep) std::erase_if(names, [&](const std::string& name) { return !keep(name); });
  std::vector<float*> planes;
  for (const std::string& name : names) planes.push_back(frame.addChannel(name).data());
  frame.attributes() = stringAttributes(in.header());
  if (names.empty()) return frame;  // the header alone: OpenEXR reads pixels into a buffer
  if (ExrCoreRows core(source, names); core.usable()) {
    core.read(planes, from, to);
    return frame;
  }
  in.setFrameBuffer(frameBufferOf(window, names, planes, window.min.y + from));
  in.readPixels(window.min.y + from, window.min.y + to - 1);
  return frame;
}

}  // namespace

FrameImage decodeExr(const std::string& bytes, const std::string& label) {
  return readBytes(bytes, label, [](Imf::InputFile& in, const ExrBytes& source) { return framePart(in, source, {}); });
}

FrameImage decodeExrFile(const std::filesystem::path& file, const std::string& label, const ChannelFilter& keep) {
  return readFile(file, label, [&](Imf::InputFile& in, const ExrBytes& source) { return framePart(in, source, keep); });
}

std::pair<int, int> readExrStrips(const std::filesystem::path& file, const std::string& label,
                                  const std::vector<std::string>& channels, int rowsPerStrip,
                                  const std::function<bool(const ExrStrip&)>& strip) {
  return readFile(file, label, [&](Imf::InputFile& exr, const ExrBytes& source) {
    return readStrips(exr, source, channels.empty() ? channelNames(exr.header()) : channels, rowsPerStrip, strip);
  });
}

namespace {

ExrHeader headerRead(Imf::InputFile& in, const ExrBytes&) {
  const Imath::Box2i window = in.header().dataWindow();
  ExrHeader header{window.max.x - window.min.x + 1, window.max.y - window.min.y + 1, channelNames(in.header()),
                   stringAttributes(in.header()), {}};
  for (auto it = in.header().channels().begin(); it != in.header().channels().end(); ++it)
    if (it.channel().type == Imf::HALF) header.halfChannels.emplace_back(it.name());
  return header;
}

}  // namespace

ExrHeader readExrHeader(const std::filesystem::path& file, const std::string& label) {
  return readFile(file, label, headerRead);
}

ExrHeader decodeExrHeader(const std::string& bytes, const std::string& label) {
  return readBytes(bytes, label, headerRead);
}

FrameImage readExrRows(const std::filesystem::path& file, const std::string& label, int from, int to,
                       const ChannelFilter& keep) {
  return readFile(file, label, [&](Imf::InputFile& in, const ExrBytes& source) {
    return framePart(in, source, keep, from, to);
  });
}

ExrScan scanExrFile(const std::filesystem::path& file, const std::string& label, int rowsPerStrip) {
  ExrScan scan;
  std::tie(scan.width, scan.height) = readExrStrips(file, label, {}, rowsPerStrip, [&](const ExrStrip& strip) {
    const auto count = static_cast<ptrdiff_t>(strip.width) * strip.rows;
    for (size_t c = 0; c < strip.names.size(); ++c) {
      const float* plane = strip.planes[c];
      const float* bad = std::find_if(plane, plane + count, [](float v) { return !std::isfinite(v); });
      if (bad == plane + count) continue;
      const auto p = static_cast<size_t>(bad - plane);
      const auto w = static_cast<size_t>(strip.width);
      scan.firstNonFinite = "channel " + strip.names[c] + " at pixel (" + std::to_string(p % w) + ", " +
                            std::to_string(static_cast<size_t>(strip.firstRow) + p / w) + ")";
      return false;
    }
    return true;
  });
  return scan;
}

void writeExr(const std::filesystem::path& file, const FrameImage& frame) {
  writeFileAtomically(file, encodeExr(frame));
}

struct ExrStripWriter::Output {
  Output(const std::filesystem::path& path, const Imf::Header& header) : file(path.c_str(), header) {}
  Imf::OutputFile file;
};

ExrStripWriter::ExrStripWriter(const std::filesystem::path& file, int width, int height,
                               const std::vector<std::string>& channels,
                               const std::map<std::string, std::string>& attributes, ExrCompression compression,
                               const ChannelFilter& halfChannels)
    : file_(file), width_(width), height_(height), channels_(channels), half_(halfChannels) {
  try {
    out_ = std::make_unique<Output>(file, headerOf(width, height, channels, attributes, compression, half_));
  } catch (const std::exception& e) {
    throw ExrError(file.string() + ": cannot write EXR: " + e.what());
  }
}

ExrStripWriter::~ExrStripWriter() = default;

void ExrStripWriter::write(const FrameImage& strip) {
  const auto refuse = [&](const std::string& why) { throw ExrError(file_.string() + ": cannot write EXR: " + why); };
  if (!out_) refuse("the file was finished");
  if (strip.width() != width_ || strip.height() > height_ - rows_)
    refuse("a " + std::to_string(strip.width()) + " x " + std::to_string(strip.height()) + " strip after row " +
           std::to_string(rows_) + " of a " + std::to_string(width_) + " x " + std::to_string(height_) + " frame");
  for (const std::string& name : channels_)
    if (!strip.hasChannel(name)) refuse("the strip lacks channel \"" + name + "\"");
  try {
    const RowsToWrite rows(width_, channels_, planesOf(strip, channels_), rows_, strip.height(), half_);
    out_->file.setFrameBuffer(rows.buffer());
    out_->file.writePixels(strip.height());
  } catch (const std::exception& e) {
    refuse(e.what());
  }
  rows_ += strip.height();
}

void ExrStripWriter::finish() {
  const bool whole = rows_ == height_;
  try {
    out_.reset();  // OpenEXR completes the file when it closes it
  } catch (const std::exception& e) {
    throw ExrError(file_.string() + ": cannot write EXR: " + e.what());
  }
  if (!whole)
    throw ExrError(file_.string() + ": cannot write EXR: " + std::to_string(rows_) + " of " + std::to_string(height_) +
                   " rows written");
}

FrameImage readExr(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw ExrError(file.string() + ": no such file or not readable");
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return decodeExr(bytes.str(), file.string());
}

void writeExrInStrips(const std::filesystem::path& file, const FrameImage& frame, ExrCompression compression,
                      const ChannelFilter& halfChannels) {
  constexpr int kStripRows = 64;
  ExrStripWriter writer(file, frame.width(), frame.height(), frame.channelNames(), frame.attributes(), compression,
                        halfChannels);
  for (int y = 0; y < frame.height(); y += kStripRows)
    writer.write(frame.crop(0, y, frame.width(), std::min(kStripRows, frame.height() - y)));
  writer.finish();
}

}  // namespace pathfarm
