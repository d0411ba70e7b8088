#include "image/exr_io.h"

#include "image/atomic_file.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStdIO.h>
#include <OpenEXR/ImfStringAttribute.h>

#include <fstream>
#include <sstream>

namespace pathfarm {

std::string encodeExr(const FrameImage& frame, ExrCompression compression) {
  try {
    Imf::Header header(frame.width(), frame.height());
    header.compression() = compression == ExrCompression::Small ? Imf::ZIP_COMPRESSION : Imf::RLE_COMPRESSION;
    for (const auto& [name, value] : frame.attributes()) header.insert(name, Imf::StringAttribute(value));
    Imf::FrameBuffer buffer;
    for (const std::string& name : frame.channelNames()) {
      header.channels().insert(name, Imf::Channel(Imf::FLOAT));
      // OpenEXR's Slice takes a non-const pointer but only reads when writing.
      auto* base = const_cast<float*>(frame.channel(name).data());
      buffer.insert(name, Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(base), sizeof(float),
                                     sizeof(float) * static_cast<size_t>(frame.width())));
    }
    Imf::StdOSStream stream;
    {
      Imf::OutputFile out(stream, header);  // finishes the file when it goes out of scope
      out.setFrameBuffer(buffer);
      out.writePixels(frame.height());
    }
    return stream.str();
  } catch (const std::exception& e) {
    throw ExrError(std::string("cannot encode EXR: ") + e.what());
  }
}

FrameImage decodeExr(const std::string& bytes, const std::string& label) {
  try {
    Imf::StdISStream stream;
    stream.str(bytes);
    Imf::InputFile in(stream);
    const Imath::Box2i window = in.header().dataWindow();
    const int width = window.max.x - window.min.x + 1;
    const int height = window.max.y - window.min.y + 1;
    FrameImage frame(width, height);
    Imf::FrameBuffer buffer;
    const size_t rowStride = sizeof(float) * static_cast<size_t>(width);
    for (auto it = in.header().channels().begin(); it != in.header().channels().end(); ++it) {
      std::vector<float>& plane = frame.addChannel(it.name());
      // OpenEXR addresses slices by absolute pixel coordinates: shift the base pointer so
      // the data window's corner lands on the plane's first element.
      char* base = reinterpret_cast<char*>(plane.data()) -
                   static_cast<ptrdiff_t>(window.min.x) * static_cast<ptrdiff_t>(sizeof(float)) -
                   static_cast<ptrdiff_t>(window.min.y) * static_cast<ptrdiff_t>(rowStride);
      buffer.insert(it.name(), Imf::Slice(Imf::FLOAT, base, sizeof(float), rowStride));
    }
    for (auto it = in.header().begin(); it != in.header().end(); ++it) {
      if (const auto* s = dynamic_cast<const Imf::StringAttribute*>(&it.attribute()))
        frame.attributes()[it.name()] = s->value();
    }
    in.setFrameBuffer(buffer);
    in.readPixels(window.min.y, window.max.y);
    return frame;
  } catch (const std::exception& e) {
    throw ExrError(label + ": cannot read EXR: " + e.what());
  }
}

void writeExr(const std::filesystem::path& file, const FrameImage& frame) {
  writeFileAtomically(file, encodeExr(frame));
}

FrameImage readExr(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw ExrError(file.string() + ": no such file or not readable");
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return decodeExr(bytes.str(), file.string());
}

}  // namespace pathfarm
