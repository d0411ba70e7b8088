// What a farm chunk's compression costs: one decomposed frame, as a keyframe's render
// tiles and assembled frame carry it (every component's buffers, `--decompose auto`),
// written and read back by OpenEXR with each lossless codec on one thread.
//
//   build/bin/chunk_compression [--scene scenes/walkthrough/scene.json] [--res 480x270]
//                               [--spp 16] [--frame 0] [--repeat 5]
//
// Prints one row per codec: the chunk's bytes, and the medians over the repeats of the
// seconds to write it, to read it with OpenEXR's Imf::InputFile into planes it has, and
// to decode it with decodeExr, new planes and all (image/exr_core_rows.h: OpenEXRCore).
// "rle" is what encodeExr's ExrCompression::Fast writes, "zip, level 6" its Small; the row
// says when encodeExr's bytes are not the codec's own. Then the frame as a d keyframe's
// chunk holds it (the channels its readers use, worker/chunk_channels.h), written by
// encodeExr all in 32-bit floats and with the farm's half floats (halfPrecisionChannels).
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStdIO.h>

#include <chrono>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "bench/command_line.h"
#include "bench/median.h"
#include "contract/pipeline.h"
#include "image/exr_io.h"
#include "renderer/integrators/frame_renderer.h"
#include "renderer/scene/scene_loader.h"
#include "renderer/setup/auto_decomposition.h"
#include "worker/chunk_channels.h"

namespace {

using namespace pathfarm;
using bench::median;
using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// Every channel of `frame` as a float slice (OpenEXR reads into and writes from the same planes).
Imf::FrameBuffer slicesOf(FrameImage& frame) {
  Imf::FrameBuffer buffer;
  for (const std::string& name : frame.channelNames())
    buffer.insert(name, Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(frame.channel(name).data()), sizeof(float),
                                   sizeof(float) * static_cast<size_t>(frame.width())));
  return buffer;
}

struct Codec {
  const char* name;
  Imf::Compression compression;
  std::optional<int> zipLevel;
  std::optional<ExrCompression> pathfarm;  // encodeExr's setting that should write the same bytes
};

struct Measured {
  size_t bytes = 0;
  double writeSeconds = 0, readSeconds = 0, decodeSeconds = 0;
  std::string encoded;
};

Measured measureOnce(FrameImage& frame, const Codec& codec) {
  Imf::Header header(frame.width(), frame.height());
  header.compression() = codec.compression;
  if (codec.zipLevel) header.zipCompressionLevel() = *codec.zipLevel;
  for (const std::string& name : frame.channelNames()) header.channels().insert(name, Imf::Channel(Imf::FLOAT));
  const Imf::FrameBuffer buffer = slicesOf(frame);
  Measured measured;
  Imf::StdOSStream out;
  Clock::time_point start = Clock::now();
  {
    Imf::OutputFile file(out, header, 1);
    file.setFrameBuffer(buffer);
    file.writePixels(frame.height());
  }
  measured.writeSeconds = secondsSince(start);
  measured.encoded = out.str();
  measured.bytes = measured.encoded.size();
  FrameImage readBack = frame;
  Imf::StdISStream in;
  in.str(measured.encoded);
  start = Clock::now();
  Imf::InputFile file(in, 1);
  file.setFrameBuffer(slicesOf(readBack));
  file.readPixels(0, frame.height() - 1);
  measured.readSeconds = secondsSince(start);
  start = Clock::now();
  const FrameImage decoded = decodeExr(measured.encoded, "chunk");
  measured.decodeSeconds = secondsSince(start);
  return measured;
}

}  // namespace

int main(int argc, char** argv) {
  bench::CommandLine app("pathfarm chunk compression benchmark");
  std::string scenePath = "scenes/walkthrough/scene.json", resolution = "480x270";
  int spp = 16, frame = 0, repeat = 5;
  app.option("--scene", scenePath);
  app.option("--res", resolution);
  app.option("--spp", spp);
  app.option("--frame", frame);
  app.option("--repeat", repeat).positive();
  if (const auto exit = app.parse(argc, argv)) return *exit;

  const Scene scene = loadScene(scenePath);
  RenderSettings settings = RenderSettings::defaultsOf(scene);
  if (std::sscanf(resolution.c_str(), "%dx%d", &settings.width, &settings.height) != 2) return 2;
  settings.spp = spp;
  settings.decomposition = decompositionFor(scene, "auto");
  FrameImage image = FrameRenderer(scene, settings).render(frame);
  image.attributes().clear();  // the codecs' rows compare pixels alone
  std::printf("%s, frame %d, %dx%d, %d spp, decomposed (auto): %zu channels, %.1f MB as floats; medians of %d\n\n",
              scenePath.c_str(), frame, image.width(), image.height(), spp, image.channelNames().size(),
              4e-6 * static_cast<double>(image.pixelCount() * image.channelNames().size()), repeat);

  const Codec codecs[] = {
      {"none", Imf::NO_COMPRESSION, {}, {}},
      {"rle", Imf::RLE_COMPRESSION, {}, ExrCompression::Fast},
      {"zip, level 1", Imf::ZIP_COMPRESSION, 1, {}},
      {"zip, level 6", Imf::ZIP_COMPRESSION, 6, ExrCompression::Small},
      {"piz", Imf::PIZ_COMPRESSION, {}, {}},
  };
  std::printf("| codec | MB | write s | read s | write + read s | decodeExr s |\n"
              "| --- | ---: | ---: | ---: | ---: | ---: |\n");
  for (const Codec& codec : codecs) {
    std::vector<double> writes, reads, decodes;
    Measured last;
    for (int i = 0; i < repeat; ++i) {
      last = measureOnce(image, codec);
      writes.push_back(last.writeSeconds);
      reads.push_back(last.readSeconds);
      decodes.push_back(last.decodeSeconds);
    }
    const bool differs = codec.pathfarm && encodeExr(image, *codec.pathfarm) != last.encoded;
    std::printf("| %s%s | %.1f | %.3f | %.3f | %.3f | %.3f |\n", codec.name,
                differs ? " (encodeExr's bytes differ)" : "", 1e-6 * static_cast<double>(last.bytes), median(writes),
                median(reads), median(writes) + median(reads), median(decodes));
  }

  FrameImage keyframe = image;
  farm::keepReadChannels(farm::ChunkContent::KeyframeRender, farm::stagesOf(farm::PIPELINE_D), keyframe);
  std::printf("\nA d keyframe's chunk (%zu channels), by encodeExr and decodeExr:\n\n"
              "| codec | precision | MB | write s | decodeExr s |\n| --- | --- | ---: | ---: | ---: |\n",
              keyframe.channelNames().size());
  for (const auto& [name, compression] : {std::pair{"rle", ExrCompression::Fast}, {"zip, level 6", ExrCompression::Small}})
    for (const bool halves : {false, true}) {
      const ChannelFilter half = halves ? farm::halfPrecisionChannels(keyframe) : ChannelFilter{};
      std::vector<double> writes, decodes;
      std::string bytes;
      for (int i = 0; i < repeat; ++i) {
        Clock::time_point start = Clock::now();
        bytes = encodeExr(keyframe, compression, half);
        writes.push_back(secondsSince(start));
        start = Clock::now();
        const FrameImage decoded = decodeExr(bytes, "chunk");
        decodes.push_back(secondsSince(start));
      }
      std::printf("| %s | %s | %.1f | %.3f | %.3f |\n", name, halves ? "the farm's halves" : "floats",
                  1e-6 * static_cast<double>(bytes.size()), median(writes), median(decodes));
    }
  return 0;
}
