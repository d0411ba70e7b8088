#include "worker/assemble_frame.h"

#include <algorithm>
#include <map>
#include <optional>
#include <set>
#include <vector>

#include "image/exr_io.h"
#include "worker/failure_class.h"
#include "worker/filter_tasks.h"

namespace pathfarm::farm {
namespace {

// Strips are at most this many rows, and end where tiles end.
constexpr int kStripRows = 64;

// A tile's place in the frame being assembled, and its file.
struct Tile {
  int input = 0;  // the lease's input index
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  std::filesystem::path file;
};

std::string labelOf(const ChunkRef& ref) { return "tile chunk " + ref.sha256(); }

// The header the frame gets from its tiles': their channels and attributes (a later tile's
// value wins), with the count of dropped samples summed.
struct FrameHeader {
  std::set<std::string> channels;
  std::set<std::string> floatSomewhere;  // channels a tile holds as 32-bit floats
  std::map<std::string, std::string> attributes;
  uint64_t nonFinite = 0;

  void add(const ExrHeader& tile, const ChunkRef& ref) {
    channels.insert(tile.channels.begin(), tile.channels.end());
    for (const std::string& name : tile.channels)
      if (std::find(tile.halfChannels.begin(), tile.halfChannels.end(), name) == tile.halfChannels.end())
        floatSomewhere.insert(name);
    for (const auto& [key, value] : tile.attributes) attributes[key] = value;
    const auto count = tile.attributes.find("pathfarm.nonfinite_samples");
    if (count == tile.attributes.end()) throw BadInput(labelOf(ref) + " was not made by a pathfarm renderer");
    nonFinite += std::stoull(count->second);
  }
};

// The rows where a strip ends: where a tile starts or ends, and every kStripRows.
std::vector<int> stripEnds(const std::vector<Tile>& tiles, int height) {
  std::set<int> ends;
  for (int y = kStripRows; y < height; y += kStripRows) ends.insert(y);
  for (const Tile& tile : tiles) ends.insert({tile.y0, tile.y1});
  ends.erase(0);
  ends.insert(height);
  return {ends.begin(), ends.end()};
}

}  // namespace

void assembleFrame(const Lease& lease, const ChunkFileFetcher& fetch, const std::filesystem::path& file,
                   std::atomic<double>& progress) {
  const ShotSpec& spec = lease.spec();
  PixelWindow whole;
  whole.set_x1(spec.width());
  whole.set_y1(spec.height());
  const PixelWindow& area = lease.params().has_window() ? lease.params().window() : whole;
  const int width = area.x1() - area.x0(), height = area.y1() - area.y0();

  // The frame's header needs every tile's attributes before its first row is written: the
  // tiles' headers first, each checked against its window.
  std::vector<Tile> tiles;
  FrameHeader header;
  for (int i = 0; i < lease.inputs_size(); ++i) {
    const ChunkRef& ref = lease.inputs(i);
    const PixelWindow& window = lease.input_params(i).window();
    Tile& tile = tiles.emplace_back(Tile{i, window.x0() - area.x0(), window.y0() - area.y0(),
                                         window.x1() - area.x0(), window.y1() - area.y0(), fetch(ref)});
    const ExrHeader read = readExrHeader(tile.file, labelOf(ref));
    if (read.width != window.x1() - window.x0() || read.height != window.y1() - window.y0() ||
        window.x0() < area.x0() || window.y0() < area.y0() || window.x1() > area.x1() || window.y1() > area.y1())
      throw BadInput(labelOf(ref) + " does not have its window's size or place");
    header.add(read, ref);
    progress = 0.5 * static_cast<double>(i + 1) / static_cast<double>(lease.inputs_size());
  }
  header.attributes["pathfarm.nonfinite_samples"] = std::to_string(header.nonFinite);
  // A shot's frame is kept; a keyframe, a measurement's frame or a region is read by the
  // next task.
  const bool keptFrame = !lease.params().has_window() &&
                         (lease.params().role() == ROLE_OUTPUT || lease.params().role() == ROLE_UNSPECIFIED);
  const std::vector<std::string> channels(header.channels.begin(), header.channels.end());
  // A channel every tile holds in half floats keeps its values in half floats.
  const ChannelFilter halfInEveryTile = [&](const std::string& name) { return !header.floatSomewhere.count(name); };
  // The tiles are the task's input; the file it writes is this worker's.
  std::optional<ExrStripWriter> writer;
  writingOutput([&] {
    writer.emplace(file, width, height, channels, header.attributes,
                   keptFrame ? ExrCompression::Small : ExrCompression::Fast, halfInEveryTile);
  });

  // Then strip by strip: the rows of every tile the strip crosses, pasted in input order.
  int top = 0;
  for (const int bottom : stripEnds(tiles, height)) {
    FrameImage strip(width, bottom - top);
    for (const std::string& name : channels) strip.addChannel(name);
    for (const Tile& tile : tiles) {
      const int from = std::max(top, tile.y0), to = std::min(bottom, tile.y1);
      if (from >= to) continue;
      const ChunkRef& ref = lease.inputs(tile.input);
      const FrameImage rows = readExrRows(tile.file, labelOf(ref), from - tile.y0, to - tile.y0);
      if (const std::string bad = rows.firstNonFinite(from - tile.y0); !bad.empty())
        throw BadInput(labelOf(ref) + " holds a non-finite value (" + bad + "): not pasted into the frame");
      strip.paste(rows, tile.x0, from - top);
    }
    writingOutput([&] { writer->write(strip); });
    top = bottom;
    progress = 0.5 + 0.5 * static_cast<double>(bottom) / static_cast<double>(height);
  }
  writingOutput([&] { writer->finish(); });
}

}  // namespace pathfarm::farm
