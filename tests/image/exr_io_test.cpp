// Multi-layer EXR frames survive a write and a read unchanged; broken files are errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>
#include <stdexcept>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfOutputFile.h>
#include <half.h>

#include "image/beauty_copy.h"
#include "image/exr_io.h"
#include "test_support.h"

namespace pathfarm {
namespace {

std::filesystem::path temporaryFile(const std::string& name) {
  return test_support::processTemporaryFolder("pathfarm_exr") / name;
}

FrameImage sampleFrame() {
  FrameImage frame(37, 23);  // odd sizes catch stride mistakes
  std::mt19937 random(5);
  std::normal_distribution<float> value(0.0f, 10.0f);
  for (const char* name : {"R", "G", "B", "diffuse_direct.color.R", "diffuse_direct.reflectance.G",
                           "reflection.normal.Z", "transmission.motion.X", "depth.Z"}) {
    for (float& v : frame.addChannel(name)) v = value(random);
  }
  frame.channel("depth.Z")[5] = std::numeric_limits<float>::infinity();
  frame.attributes()["pathfarm.frame"] = "12";
  frame.attributes()["pathfarm.decomposition"] = "diffuse_direct=ED,residual";
  return frame;
}

TEST(ExrIo, MultiLayerRoundTripIsExact) {
  const FrameImage original = sampleFrame();
  const auto file = temporaryFile("roundtrip.exr");
  writeExr(file, original);
  const FrameImage loaded = readExr(file);
  EXPECT_EQ(loaded.width(), original.width());
  EXPECT_EQ(loaded.height(), original.height());
  ASSERT_EQ(loaded.channelNames().size(), original.channelNames().size());
  for (const std::string& name : original.channelNames()) {
    ASSERT_TRUE(loaded.hasChannel(name)) << name;
    EXPECT_EQ(loaded.channel(name), original.channel(name)) << name;
  }
  EXPECT_EQ(loaded.attributes().at("pathfarm.frame"), "12");
  EXPECT_EQ(loaded.attributes().at("pathfarm.decomposition"), "diffuse_direct=ED,residual");
  for (const auto& entry : std::filesystem::directory_iterator(file.parent_path()))
    EXPECT_EQ(entry.path().string().find(file.string() + "."), std::string::npos) << "left behind: " << entry.path();
  std::filesystem::remove(file);
}

// The beauty copy holds R, G, B alone, bit for bit, over more rows than one strip.
TEST(ExrIo, ABeautyCopyHoldsTheBeautyAndTheAttributesAlone) {
  FrameImage original(19, 150);
  std::mt19937 random(9);
  std::uniform_real_distribution<float> value(0.0f, 4.0f);
  for (const char* name : {"R", "G", "B", "diffuse_direct.color.R", "variance.G"})
    for (float& v : original.addChannel(name)) v = value(random);
  original.attributes()["pathfarm.frame"] = "7";
  const auto frame = temporaryFile("full.exr"), copy = temporaryFile("beauty.exr");
  writeExr(frame, original);
  writeBeautyCopy(frame, copy);
  const FrameImage beauty = readExr(copy);
  EXPECT_EQ(beauty.width(), 19);
  EXPECT_EQ(beauty.height(), 150);
  EXPECT_EQ(beauty.channelNames().size(), 3u);
  for (const char* name : {"R", "G", "B"}) EXPECT_EQ(beauty.channel(name), original.channel(name)) << name;
  EXPECT_EQ(beauty.attributes().at("pathfarm.frame"), "7");
  EXPECT_THROW(writeBeautyCopy(temporaryFile("missing.exr"), copy), ExrError);
  std::filesystem::remove(frame);
  std::filesystem::remove(copy);
}

TEST(ExrIo, MissingAndTruncatedFilesAreErrorsNamingTheFile) {
  EXPECT_THROW(readExr(temporaryFile("does_not_exist.exr")), ExrError);
  const auto file = temporaryFile("truncated.exr");
  writeExr(file, sampleFrame());
  const auto size = std::filesystem::file_size(file);
  for (const auto keep : {size / 2, size_t{300}, size_t{10}, size_t{0}}) {
    std::filesystem::resize_file(file, keep);
    try {
      readExr(file);
      FAIL() << "a file truncated to " << keep << " bytes was read";
    } catch (const ExrError& e) {
      EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos);
    }
  }
  std::filesystem::remove(file);
}

TEST(ExrIo, BytesInMemoryMatchTheFile) {
  const FrameImage original = sampleFrame();
  const auto file = temporaryFile("memory.exr");
  writeExr(file, original);
  std::ifstream in(file, std::ios::binary);
  const std::string onDisk{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  EXPECT_EQ(encodeExr(original), onDisk);
  EXPECT_EQ(decodeExr(onDisk, "chunk").channel("reflection.normal.Z"), original.channel("reflection.normal.Z"));
  std::string damaged = onDisk;
  damaged.resize(damaged.size() / 3);
  try {
    decodeExr(damaged, "chunk 1f2e");
    FAIL() << "damaged bytes were decoded";
  } catch (const ExrError& e) {
    EXPECT_NE(std::string(e.what()).find("chunk 1f2e"), std::string::npos);
  }
  std::filesystem::remove(file);
}

// The bytes of `chunk` with the little-endian int32 at `offset` replaced.
std::string withInt32(std::string chunk, size_t offset, int32_t value) {
  for (int i = 0; i < 4; ++i) chunk[offset + static_cast<size_t>(i)] = static_cast<char>(static_cast<uint32_t>(value) >> (8 * i));
  return chunk;
}

// What bench/fuzz.sh --target exr_chunk found: a chunk whose data window was widened to
// 50331656 pixels made decodeExr allocate 1 GB and spend 3 s before OpenEXR found the
// pixels missing.
// An 8x4 RGB chunk whose data window claims 2000000 x 4 pixels: 96 MB of planes from a few
// hundred bytes (the fuzzer's case asked for 1 GB).
std::string widenedChunk() {
  FrameImage tile(8, 4);
  for (const char* name : {"R", "G", "B"}) tile.addChannel(name);
  const std::string chunk = encodeExr(tile, ExrCompression::Fast);
  const size_t box = chunk.find(std::string("dataWindow\0box2i\0", 17));
  if (box == std::string::npos) throw std::logic_error("the chunk has no data window");
  return withInt32(chunk, box + 17 + 4 + 8, 1'999'999);  // after the name, type and size: xMin, yMin, xMax
}

TEST(ExrIo, AChunkClaimingMorePixelsThanItsBytesCanHoldIsRefusedBeforeDecoding) {
  try {
    decodeExr(widenedChunk(), "chunk 9a7b");
    FAIL() << "a chunk claiming 2000000 x 4 pixels was decoded";
  } catch (const ExrError& e) {
    EXPECT_NE(std::string(e.what()).find("chunk 9a7b"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("data window of 2000000 x 4 pixels and 3 channels"), std::string::npos)
        << e.what();
  }
}

TEST(ExrIo, AScanInStripsFindsTheSizeAndTheFirstNonFiniteValueThatDecodingWholeFinds) {
  const std::filesystem::path file = temporaryFile("scanned.exr");
  const auto scan = [&](const std::string& bytes, int rows) {
    std::ofstream(file, std::ios::binary | std::ios::trunc) << bytes;
    return scanExrFile(file, "chunk", rows);
  };
  FrameImage frame = sampleFrame();
  frame.channel("depth.Z")[5] = 0.0f;
  const std::string finite = encodeExr(frame, ExrCompression::Fast);
  const ExrScan clean = scan(finite, 4);
  EXPECT_EQ(clean.width, 37);
  EXPECT_EQ(clean.height, 23);
  EXPECT_EQ(clean.firstNonFinite, "");
  // A NaN in the last row, in a strip of its own (23 rows in strips of 4, 5 and 1), then
  // an infinity in an earlier strip of a later channel: the first row wins.
  frame.channel("reflection.normal.Z")[22 * 37 + 36] = std::numeric_limits<float>::quiet_NaN();
  for (const int rows : {1, 4, 5, 23, 100}) {
    EXPECT_EQ(scan(encodeExr(frame), rows).firstNonFinite, "channel reflection.normal.Z at pixel (36, 22)")
        << rows << " rows a strip";
    EXPECT_EQ(scan(encodeExr(frame), rows).firstNonFinite, decodeExr(encodeExr(frame), "chunk").firstNonFinite());
  }
  frame.channel("transmission.motion.X")[3 * 37 + 2] = std::numeric_limits<float>::infinity();
  EXPECT_EQ(scan(encodeExr(frame), 4).firstNonFinite, "channel transmission.motion.X at pixel (2, 3)");
  EXPECT_THROW(scan(finite.substr(0, finite.size() / 2), 4), ExrError);
  EXPECT_THROW(scanExrFile(temporaryFile("absent.exr"), "chunk"), ExrError);
}

std::string fileBytes(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(ExrIo, AFrameWrittenInStripsIsTheFileEncodingItWholeMakes) {
  const FrameImage frame = sampleFrame();
  for (const ExrCompression compression : {ExrCompression::Small, ExrCompression::Fast}) {
    const std::filesystem::path file = temporaryFile("strips.exr");
    ExrStripWriter writer(file, frame.width(), frame.height(), frame.channelNames(), frame.attributes(), compression);
    // 23 rows as 1, 16 and 6: strips across ZIP's 16-row blocks.
    for (const auto& [top, rows] : {std::pair{0, 1}, {1, 16}, {17, 6}}) {
      writer.write(frame.crop(0, top, frame.width(), rows));
      EXPECT_EQ(writer.rowsWritten(), top + rows);
    }
    writer.finish();
    EXPECT_EQ(fileBytes(file), encodeExr(frame, compression));
  }
}

TEST(ExrIo, AStripWriterRefusesRowsItCannotPlaceAndAShortFrame) {
  const FrameImage frame = sampleFrame();
  ExrStripWriter writer(temporaryFile("refused.exr"), frame.width(), frame.height(), frame.channelNames(),
                        frame.attributes(), ExrCompression::Fast);
  EXPECT_THROW(writer.write(frame.crop(0, 0, 36, 2)), ExrError);  // not the frame's width
  FrameImage lacking(frame.width(), 2);
  lacking.addChannel("R");
  EXPECT_THROW(writer.write(lacking), ExrError);  // not every channel
  writer.write(frame.crop(0, 0, frame.width(), 20));
  EXPECT_THROW(writer.write(frame.crop(0, 0, frame.width(), 4)), ExrError);  // past the last row
  EXPECT_THROW(writer.finish(), ExrError);  // 20 of 23 rows
  EXPECT_THROW(ExrStripWriter(temporaryFile("absent") / "frame.exr", 4, 4, {"R"}, {}, ExrCompression::Fast), ExrError);
}

// A frame written a strip at a time (a task's large output) is encodeExr's bytes, for a
// frame of more rows than a strip.
TEST(ExrIo, AFrameWrittenInStripsIsItsEncodedBytes) {
  FrameImage tall(5, 150);
  std::mt19937 random(3);
  std::normal_distribution<float> value(0.0f, 1.0f);
  for (const char* name : {"R", "G", "B", "diffuse_direct.color.R"})
    for (float& v : tall.addChannel(name)) v = value(random);
  tall.attributes()["pathfarm.frame"] = "3";
  for (const ExrCompression compression : {ExrCompression::Fast, ExrCompression::Small}) {
    const std::filesystem::path file = temporaryFile("strips.exr");
    writeExrInStrips(file, tall, compression);
    EXPECT_TRUE(fileBytes(file) == encodeExr(tall, compression));
  }
}

TEST(ExrIo, AFilesHeaderAndRowsReadInPlaceAreWhatDecodingItWholeGives) {
  const FrameImage frame = sampleFrame();
  const std::filesystem::path file = temporaryFile("rows.exr");
  writeExr(file, frame);
  const ExrHeader header = readExrHeader(file, "chunk");
  const FrameImage decoded = readExr(file);
  EXPECT_EQ(header.width, 37);
  EXPECT_EQ(header.height, 23);
  EXPECT_EQ(header.channels, decoded.channelNames());
  EXPECT_EQ(header.attributes, frame.attributes());
  // Rows across ZIP's 16-row blocks, and the last row alone.
  for (const auto& [from, to] : {std::pair{0, 23}, {5, 19}, {22, 23}}) {
    const FrameImage rows = readExrRows(file, "chunk", from, to);
    const FrameImage expected = frame.crop(0, from, frame.width(), to - from);
    ASSERT_EQ(rows.channelNames(), decoded.channelNames());
    for (const std::string& name : expected.channelNames())
      EXPECT_EQ(rows.channel(name), expected.channel(name)) << name << " rows " << from << " to " << to;
  }
  EXPECT_THROW(readExrRows(file, "chunk", 20, 24), ExrError);
  EXPECT_THROW(readExrRows(file, "chunk", 4, 4), ExrError);
  // Rows of some channels: those channels alone, the same values.
  const std::string kept = decoded.channelNames().back();
  const FrameImage some = readExrRows(file, "chunk", 5, 19, [&](const std::string& name) { return name == kept; });
  EXPECT_EQ(some.channelNames(), std::vector<std::string>{kept});
  EXPECT_EQ(some.channel(kept), frame.crop(0, 5, frame.width(), 14).channel(kept));
  EXPECT_EQ(some.attributes(), frame.attributes());
  const std::string bytes = fileBytes(file);
  std::ofstream(file, std::ios::binary | std::ios::trunc) << bytes.substr(0, 40);
  EXPECT_THROW(readExrHeader(file, "chunk"), ExrError);
  EXPECT_THROW(readExrHeader(temporaryFile("absent.exr"), "chunk"), ExrError);
}

// decodeExrFile reads the file in place and gives what decodeExr gives of its bytes; a
// truncated or widened file is an error naming its label.
TEST(ExrIo, AFileDecodedInPlaceIsItsBytesDecoded) {
  const std::filesystem::path file = temporaryFile("in_place.exr");
  writeExr(file, sampleFrame());
  const FrameImage inPlace = decodeExrFile(file, "chunk 51ab"), fromBytes = decodeExr(fileBytes(file), "bytes");
  ASSERT_EQ(inPlace.channelNames(), fromBytes.channelNames());
  for (const std::string& name : inPlace.channelNames()) EXPECT_EQ(inPlace.channel(name), fromBytes.channel(name)) << name;
  EXPECT_EQ(inPlace.attributes(), fromBytes.attributes());
  const std::string bytes = fileBytes(file);
  for (const std::string& damaged : {bytes.substr(0, bytes.size() / 2), widenedChunk()}) {
    std::ofstream(file, std::ios::binary | std::ios::trunc) << damaged;
    try {
      decodeExrFile(file, "chunk 51ab");
      FAIL() << "a damaged file was decoded";
    } catch (const ExrError& e) {
      EXPECT_NE(std::string(e.what()).find("chunk 51ab"), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(decodeExrFile(temporaryFile("absent.exr"), "chunk"), ExrError);
}

// With a channel filter, decodeExrFile gives the channels it accepts, as decoding the
// whole file has them, and every attribute; nothing else.
TEST(ExrIo, AFileDecodedForSomeChannelsHasThoseAlone) {
  const std::filesystem::path file = temporaryFile("some_channels.exr");
  const FrameImage whole = sampleFrame();
  writeExr(file, whole);
  const auto ofDiffuse = [](const std::string& name) { return name.rfind("diffuse_direct.", 0) == 0; };
  const FrameImage part = decodeExrFile(file, "chunk", ofDiffuse);
  std::vector<std::string> expected;
  for (const std::string& name : whole.channelNames())
    if (ofDiffuse(name)) expected.push_back(name);
  ASSERT_FALSE(expected.empty());
  ASSERT_LT(expected.size(), whole.channelNames().size());
  std::vector<std::string> names = part.channelNames();
  std::sort(names.begin(), names.end());
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(names, expected);
  for (const std::string& name : names) EXPECT_EQ(part.channel(name), whole.channel(name)) << name;
  EXPECT_EQ(part.attributes(), whole.attributes());
  EXPECT_EQ(part.width(), whole.width());
  EXPECT_EQ(part.height(), whole.height());
}

// The scan walks the headers before OpenEXR does, as decodeExr does: a damaged size is
// refused before anything is allocated.
TEST(ExrIo, AScannedFileClaimingMorePixelsThanItsBytesCanHoldIsRefused) {
  const std::filesystem::path file = temporaryFile("widened.exr");
  std::ofstream(file, std::ios::binary | std::ios::trunc) << widenedChunk();
  try {
    scanExrFile(file, "chunk 9a7b");
    FAIL() << "a chunk claiming 2000000 x 4 pixels was scanned";
  } catch (const ExrError& e) {
    EXPECT_NE(std::string(e.what()).find("data window of 2000000 x 4 pixels"), std::string::npos) << e.what();
  }
}

// Also found by the fuzzer: OpenEXR allocates what a header attribute claims before it
// reads it, 1.6 GB for a damaged size; and it reads a channel list to its end whatever
// size it declares, so the attributes after it were read from the wrong place.
TEST(ExrIo, ATiledChunkDeclaringTilesTallerThanItsBytesCanHoldIsRefusedBeforeDecoding) {
  // The fuzzer's case: 483 bytes whose tile description asked for 8 x 65 million pixel
  // tiles, for which OpenEXR allocated 3.1 GB before reading a pixel. Here a tiled seed of
  // the fuzz corpus, decodable as it is, with its tiles made 65 million pixels tall.
  std::ifstream in(test_support::sourceDir() / "fuzz/corpus/exr_chunk/tiled_zips.exr", std::ios::binary);
  const std::string chunk{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  ASSERT_NO_THROW(decodeExr(chunk, "chunk"));
  const size_t tiles = chunk.find(std::string("tiles\0tiledesc\0", 15));
  ASSERT_NE(tiles, std::string::npos);
  const std::string tall = withInt32(chunk, tiles + 15 + 4 + 4, 65'470'472);  // after the size and the x size
  // Without a data window, OpenEXR reads the header with its default one, 64 x 64 pixels.
  std::string windowless = tall;
  const size_t window = windowless.find(std::string("dataWindow\0", 11));
  ASSERT_NE(window, std::string::npos);
  windowless[window + 9] = 'X';
  for (const std::string& bytes : {tall, windowless}) {
    try {
      decodeExr(bytes, "chunk 9a7b");
      FAIL() << "a chunk declaring 65470472 pixel tall tiles was decoded";
    } catch (const ExrError& e) {
      EXPECT_NE(std::string(e.what()).find("chunk 9a7b"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("x 65470472 pixel tiles"), std::string::npos) << e.what();
    }
  }
}

TEST(ExrIo, AHeaderAttributeLargerThanTheChunkIsRefused) {
  const std::string chunk = encodeExr(sampleFrame(), ExrCompression::Fast);
  // "pathfarm.frame" made of a type OpenEXR does not know, which it keeps as bytes.
  const size_t frame = chunk.find(std::string("pathfarm.frame\0string\0", 22));
  ASSERT_NE(frame, std::string::npos);
  std::string unknown = chunk;
  unknown.replace(frame + 15, 6, "opaque");
  EXPECT_NO_THROW(decodeExr(unknown, "chunk"));
  try {
    decodeExr(withInt32(unknown, frame + 22, 0x635e7800), "chunk 9a7b");
    FAIL() << "a header attribute claiming 1.6 GB was read";
  } catch (const ExrError& e) {
    EXPECT_NE(std::string(e.what()).find("\"pathfarm.frame\" claims 1667135488 bytes"), std::string::npos) << e.what();
  }
  const size_t channels = chunk.find(std::string("channels\0chlist\0", 16));
  ASSERT_NE(channels, std::string::npos);
  const size_t size = channels + 16;
  const int32_t declared = static_cast<int32_t>(static_cast<unsigned char>(chunk[size])) |
                           static_cast<unsigned char>(chunk[size + 1]) << 8;
  try {
    decodeExr(withInt32(chunk, size, declared - 1), "chunk");
    FAIL() << "a channel list one byte longer than its declared size was read";
  } catch (const ExrError& e) {
    EXPECT_NE(std::string(e.what()).find("\"channels\" (chlist): the list runs past its declared size"),
              std::string::npos)
        << e.what();
  }
}

TEST(ExrIo, PasteCopiesAPartIntoItsPlace) {
  FrameImage frame(4, 3), part(2, 2);
  part.addChannel("R") = {1, 2, 3, 4};
  frame.paste(part, 2, 1);
  EXPECT_EQ(frame.channel("R"), (std::vector<float>{0, 0, 0, 0, 0, 0, 1, 2, 0, 0, 3, 4}));
  EXPECT_THROW(frame.paste(part, 3, 1), std::invalid_argument);
}

TEST(ExrIo, MissingChannelIsAClearError) {
  const FrameImage frame = sampleFrame();
  try {
    frame.channel("emission.color.R");
    FAIL();
  } catch (const std::out_of_range& e) {
    EXPECT_NE(std::string(e.what()).find("emission.color.R"), std::string::npos);
  }
}

// Every float's bits as it was encoded, whatever they are (NaNs with payloads, negative
// zero, subnormals), for both compressions, whole and by rows that cut ZIP's 16-row
// chunks; and every reader of the file: in memory, in place, in strips.
TEST(ExrIo, EveryBitPatternSurvivesEachCompressionAndEachReader) {
  FrameImage frame(29, 41);
  std::mt19937 random(11);
  for (const char* name : {"R", "G", "B", "residual.normal.X", "variance.B"})
    for (float& v : frame.addChannel(name)) {
      const uint32_t bits = random();
      std::memcpy(&v, &bits, sizeof v);
    }
  const auto sameBits = [](const std::vector<float>& a, const std::vector<float>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
  };
  for (const ExrCompression compression : {ExrCompression::Fast, ExrCompression::Small}) {
    const std::string bytes = encodeExr(frame, compression);
    const std::filesystem::path file = temporaryFile("bits.exr");
    std::ofstream(file, std::ios::binary | std::ios::trunc) << bytes;
    const FrameImage inMemory = decodeExr(bytes, "bits"), inPlace = decodeExrFile(file, "bits");
    for (const std::string& name : frame.channelNames()) {
      EXPECT_TRUE(sameBits(inMemory.channel(name), frame.channel(name))) << name;
      EXPECT_TRUE(sameBits(inPlace.channel(name), frame.channel(name))) << name;
    }
    for (const auto& [from, to] : {std::pair{3, 17}, {16, 32}, {31, 41}, {40, 41}}) {
      const FrameImage rows = readExrRows(file, "bits", from, to);
      const FrameImage expected = frame.crop(0, from, frame.width(), to - from);
      for (const std::string& name : frame.channelNames())
        EXPECT_TRUE(sameBits(rows.channel(name), expected.channel(name))) << name << " rows " << from << " to " << to;
    }
    int stripRows = 0;
    readExrStrips(file, "bits", {"variance.B", "G"}, 7, [&](const ExrStrip& strip) {
      for (size_t c = 0; c < strip.names.size(); ++c) {
        const std::vector<float>& whole = frame.channel(strip.names[c]);
        EXPECT_EQ(std::memcmp(strip.planes[c], whole.data() + static_cast<size_t>(strip.firstRow) * 29,
                              static_cast<size_t>(strip.rows) * 29 * sizeof(float)),
                  0)
            << strip.names[c] << " from row " << strip.firstRow;
      }
      stripRows += strip.rows;
      return true;
    });
    EXPECT_EQ(stripRows, 41);
    // One plane a channel: a channel asked for twice is refused, not half read.
    EXPECT_THROW(readExrStrips(file, "bits", {"G", "B", "G"}, 7, [](const ExrStrip&) { return true; }), ExrError);
    EXPECT_THROW(readExrStrips(file, "bits", {"A"}, 7, [](const ExrStrip&) { return true; }), ExrError);
  }
}

// The farm's intermediate chunks store some channels as 16-bit floats (exr_io.h). Every
// reader gives back the nearest half of each value (Imath's rounding, an independent
// conversion), which is within the precision exr_io.h promises; the other channels keep
// their bits.
TEST(ExrIo, HalfChannelsComeBackAsTheNearestHalfFromEveryReader) {
  FrameImage frame(29, 41);
  std::mt19937 random(17);
  std::uniform_real_distribution<float> exponent(-30.0f, 15.9f);
  for (const char* name : {"R", "G", "B", "residual.normal.X", "variance.B"})
    for (float& v : frame.addChannel(name)) v = (random() % 2 ? -1.0f : 1.0f) * std::exp2(exponent(random));
  frame.channel("G")[7] = 0.0f;
  frame.channel("G")[8] = 65504.0f;
  const ChannelFilter half = [](const std::string& name) { return name != "variance.B"; };
  const auto checkValues = [&](const FrameImage& read, int firstRow, const std::string& reader) {
    for (const std::string& name : read.channelNames()) {
      const std::vector<float>& wrote = frame.channel(name);
      for (size_t i = 0; i < read.pixelCount(); ++i) {
        const float v = wrote[static_cast<size_t>(firstRow) * 29 + i], got = read.channel(name)[i];
        if (!half(name)) {
          ASSERT_EQ(std::memcmp(&v, &got, sizeof v), 0) << reader << ": " << name << " at " << i;
          continue;
        }
        ASSERT_EQ(got, static_cast<float>(::half(v))) << reader << ": " << name << " at " << i;
        const float bound = std::abs(v) >= std::exp2(-14.0f) ? std::exp2(-11.0f) * std::abs(v) : std::exp2(-25.0f);
        ASSERT_LE(std::abs(got - v), bound) << reader << ": " << name << " at " << i;
      }
    }
  };
  for (const ExrCompression compression : {ExrCompression::Fast, ExrCompression::Small}) {
    const std::string bytes = encodeExr(frame, compression, half);
    EXPECT_LT(bytes.size(), encodeExr(frame, compression).size());
    const std::filesystem::path file = temporaryFile("halves.exr"), strips = temporaryFile("halves_in_strips.exr");
    std::ofstream(file, std::ios::binary | std::ios::trunc) << bytes;
    writeExrInStrips(strips, frame, compression, half);
    std::ifstream in(strips, std::ios::binary);
    EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), bytes);
    checkValues(decodeExr(bytes, "halves"), 0, "decodeExr");
    checkValues(decodeExrFile(file, "halves"), 0, "decodeExrFile");
    checkValues(readExrRows(file, "halves", 5, 33), 5, "readExrRows");
    const ExrHeader header = readExrHeader(file, "halves");
    EXPECT_EQ(header.halfChannels, (std::vector<std::string>{"B", "G", "R", "residual.normal.X"}));
  }
}

TEST(ExrIo, AValueAHalfCannotHoldIsRefusedNotWrittenAsInfinity) {
  for (const float bad : {65520.0f, -1e9f, std::numeric_limits<float>::infinity(), std::nanf("")}) {
    FrameImage frame(4, 3);
    frame.addChannel("R")[5] = bad;
    EXPECT_FALSE(fitsHalf(frame.channel("R"))) << bad;
    const ChannelFilter half = [](const std::string&) { return true; };
    EXPECT_THROW(encodeExr(frame, ExrCompression::Fast, half), ExrError) << bad;
    EXPECT_THROW(writeExrInStrips(temporaryFile("refused.exr"), frame, ExrCompression::Fast, half), ExrError) << bad;
  }
  EXPECT_TRUE(fitsHalf({0.0f, -65504.0f, 65504.0f, 1e-30f}));
}

// Another tool's files: half floats (ZIP), which OpenEXRCore unpacks into floats, and
// floats packed by PIZ, which image/exr_core_rows.h leaves to Imf::InputFile. Each value
// is read as the float it was.
TEST(ExrIo, HalfFloatsAndPizFilesAreReadAsWritten) {
  const int width = 5, height = 37;
  const auto valueAt = [](int index) { return 0.25f * static_cast<float>(index) - 3.0f; };  // exact in half
  for (const auto& [type, compression] : {std::pair{Imf::HALF, Imf::ZIP_COMPRESSION}, {Imf::FLOAT, Imf::PIZ_COMPRESSION}}) {
    const std::filesystem::path file = temporaryFile("other_tool.exr");
    std::vector<half> halves(width * height);
    std::vector<float> floats(width * height);
    for (int i = 0; i < width * height; ++i) {
      halves[static_cast<size_t>(i)] = half(valueAt(i));
      floats[static_cast<size_t>(i)] = valueAt(i);
    }
    {
      Imf::Header header(width, height);
      header.compression() = compression;
      header.channels().insert("Y", Imf::Channel(type));
      char* base = type == Imf::HALF ? reinterpret_cast<char*>(halves.data()) : reinterpret_cast<char*>(floats.data());
      const size_t size = type == Imf::HALF ? sizeof(half) : sizeof(float);
      Imf::FrameBuffer buffer;
      buffer.insert("Y", Imf::Slice(type, base, size, size * width));
      Imf::OutputFile out(file.c_str(), header);
      out.setFrameBuffer(buffer);
      out.writePixels(height);
    }
    for (const auto& [from, to] : {std::pair{0, height}, {2, 35}}) {
      const FrameImage read = readExrRows(file, "other tool", from, to);
      for (int y = from; y < to; ++y)
        for (int x = 0; x < width; ++x)
          ASSERT_EQ(read.channel("Y")[static_cast<size_t>((y - from) * width + x)], valueAt(y * width + x))
              << (type == Imf::HALF ? "half" : "piz") << " at (" << x << ", " << y << ")";
    }
  }
}

}  // namespace
}  // namespace pathfarm
