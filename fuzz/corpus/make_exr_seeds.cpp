// Writes the EXR chunk fuzzer's seed corpus (fuzz/corpus/exr_chunk/): chunks as the farm
// writes them (encodeExr, RLE and ZIP, layered channels, attributes), and files OpenEXR
// can also hand a worker: a shifted data window, half and uint channels, PIZ, no
// compression, tiles. Build and run from the repository's root:
//   g++ -std=c++20 -I. fuzz/corpus/make_exr_seeds.cpp image/exr_io.cpp image/frame_image.cpp \
//     image/atomic_file.cpp $(pkg-config --cflags --libs OpenEXR) -o /tmp/make_exr_seeds
//   /tmp/make_exr_seeds fuzz/corpus/exr_chunk
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStdIO.h>
#include <OpenEXR/ImfTiledOutputFile.h>
#include <Imath/half.h>

#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "image/exr_io.h"

namespace {

void save(const std::string& folder, const std::string& name, const std::string& bytes) {
  std::ofstream(folder + "/" + name, std::ios::binary) << bytes;
  std::printf("wrote %s/%s (%zu bytes)\n", folder.c_str(), name.c_str(), bytes.size());
}

pathfarm::FrameImage gradient(int width, int height, const std::vector<std::string>& channels) {
  pathfarm::FrameImage frame(width, height);
  for (size_t c = 0; c < channels.size(); ++c) {
    std::vector<float>& plane = frame.addChannel(channels[c]);
    for (size_t p = 0; p < plane.size(); ++p) plane[p] = static_cast<float>(p % 7) * 0.25f + static_cast<float>(c);
  }
  return frame;
}

// R as half, id as uint, Z as float, over `window`, with `compression`.
std::string scanlines(const Imath::Box2i& window, Imf::Compression compression) {
  const int width = window.max.x - window.min.x + 1, height = window.max.y - window.min.y + 1;
  Imf::Header header(window, window);
  header.compression() = compression;
  header.channels().insert("R", Imf::Channel(Imf::HALF));
  header.channels().insert("id", Imf::Channel(Imf::UINT));
  header.channels().insert("Z", Imf::Channel(Imf::FLOAT));
  std::vector<half> r(static_cast<size_t>(width * height), half(0.5f));
  std::vector<unsigned> id(r.size(), 3);
  std::vector<float> z(r.size(), 2.0f);
  const auto offset = static_cast<ptrdiff_t>(window.min.x) + static_cast<ptrdiff_t>(window.min.y) * width;
  Imf::FrameBuffer buffer;
  buffer.insert("R", Imf::Slice(Imf::HALF, reinterpret_cast<char*>(r.data() - offset), sizeof(half), sizeof(half) * width));
  buffer.insert("id", Imf::Slice(Imf::UINT, reinterpret_cast<char*>(id.data() - offset), sizeof(unsigned),
                                 sizeof(unsigned) * width));
  buffer.insert("Z", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(z.data() - offset), sizeof(float), sizeof(float) * width));
  Imf::StdOSStream stream;
  {
    Imf::OutputFile out(stream, header);
    out.setFrameBuffer(buffer);
    out.writePixels(height);
  }
  return stream.str();
}

std::string tiled(int width, int height) {
  Imf::Header header(width, height);
  header.compression() = Imf::ZIPS_COMPRESSION;
  header.setTileDescription(Imf::TileDescription(8, 8, Imf::ONE_LEVEL));
  header.channels().insert("Y", Imf::Channel(Imf::FLOAT));
  std::vector<float> y(static_cast<size_t>(width * height), 1.5f);
  Imf::FrameBuffer buffer;
  buffer.insert("Y", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(y.data()), sizeof(float), sizeof(float) * width));
  Imf::StdOSStream stream;
  {
    Imf::TiledOutputFile out(stream, header);
    out.setFrameBuffer(buffer);
    out.writeTiles(0, out.numXTiles() - 1, 0, out.numYTiles() - 1);
  }
  return stream.str();
}

}  // namespace

int main(int argc, char** argv) {
  const std::string folder = argc > 1 ? argv[1] : "fuzz/corpus/exr_chunk";
  pathfarm::FrameImage tile = gradient(8, 4, {"R", "G", "B", "diffuse_direct.color.R", "motion.X"});
  tile.attributes()["pathfarm.tile"] = "0 0 8 4";
  tile.attributes()["pathfarm.spp"] = "16";
  save(folder, "tile_rle.exr", pathfarm::encodeExr(tile, pathfarm::ExrCompression::Fast));
  save(folder, "frame_zip.exr", pathfarm::encodeExr(gradient(5, 3, {"R", "G", "B"}), pathfarm::ExrCompression::Small));
  save(folder, "pixel.exr", pathfarm::encodeExr(gradient(1, 1, {"Y"}), pathfarm::ExrCompression::Fast));
  save(folder, "window_piz.exr", scanlines(Imath::Box2i({-2, 3}, {5, 6}), Imf::PIZ_COMPRESSION));
  save(folder, "window_none.exr", scanlines(Imath::Box2i({1, 1}, {3, 2}), Imf::NO_COMPRESSION));
  save(folder, "tiled_zips.exr", tiled(12, 10));
  return 0;
}
