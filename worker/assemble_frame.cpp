#include "worker/assemble_frame.h"

#include <algorithm>
#include <map>
#include <optional>
#include <set>
#include <vector>

#include "image/exr_io.h"
#include "worker/failure_class.h"

namespace pathfarm::farm {
namespace {

// Strips are at most this many rows, and end where tiles end.
constexpr int kStripRows = 64;

// A tile's place in the frame being assembled, and its bytes while they are kept.
struct Tile {
  int input = 0;  // the lease's input index
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  std::optional<std::string> bytes;
};

std::string labelOf(const ChunkRef& ref) { return "tile chunk " + ref.sha256(); }

// The header the frame gets from its tiles': their channels and attributes (a later tile's
// value wins), with the count of dropped samples summed.
struct FrameHeader {
  std::set<std::string> channels;
  std::map<std::string, std::string> attributes;
  uint64_t nonFinite = 0;

  void add(const ExrHeader& tile, const ChunkRef& ref) {
    channels.insert(tile.channels.begin(), tile.channels.end());
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

void assembleFrame(const Lease& lease, const std::function<std::string(const ChunkRef&)>& fetch,
                   const std::filesystem::path& file, std::atomic<double>& progress, uint64_t keptTileBytes) {
  const ShotSpec& spec = lease.spec();
  PixelWindow whole;
  whole.set_x1(spec.width());
  whole.set_y1(spec.height());
  const PixelWindow& area = lease.params().has_window() ? lease.params().window() : whole;
  const int width = area.x1() - area.x0(), height = area.y1() - area.y0();

  // First reading: every tile's header, checked against its window.
  std::vector<Tile> tiles;
  FrameHeader header;
  uint64_t kept = 0;
  for (int i = 0; i < lease.inputs_size(); ++i) {
    const ChunkRef& ref = lease.inputs(i);
    std::string bytes = fetch(ref);
    const ExrHeader tile = readExrHeader(bytes, labelOf(ref));
    const PixelWindow& window = lease.input_params(i).window();
    if (tile.width != window.x1() - window.x0() || tile.height != window.y1() - window.y0() ||
        window.x0() < area.x0() || window.y0() < area.y0() || window.x1() > area.x1() || window.y1() > area.y1())
      throw BadInput(labelOf(ref) + " does not have its window's size or place");
    header.add(tile, ref);
    Tile& placed = tiles.emplace_back(Tile{i, window.x0() - area.x0(), window.y0() - area.y0(),
                                           window.x1() - area.x0(), window.y1() - area.y0(), std::nullopt});
    if (kept + bytes.size() <= keptTileBytes) {
      kept += bytes.size();
      placed.bytes = std::move(bytes);
    }
    progress = 0.5 * static_cast<double>(i + 1) / static_cast<double>(lease.inputs_size());
  }
  header.attributes["pathfarm.nonfinite_samples"] = std::to_string(header.nonFinite);
  // A shot's frame is kept; a keyframe, a measurement's frame or a region is read by the
  // next task.
  const bool keptFrame = !lease.params().has_window() &&
                         (lease.params().role() == ROLE_OUTPUT || lease.params().role() == ROLE_UNSPECIFIED);
  const std::vector<std::string> channels(header.channels.begin(), header.channels.end());
  ExrStripWriter writer(file, width, height, channels, header.attributes,
                        keptFrame ? ExrCompression::Small : ExrCompression::Fast);

  // Second reading: strip by strip, each tile decoded when the first strip it crosses is
  // written and let go after the last. Tiles are pasted in input order, as they are listed.
  std::vector<size_t> byTop(tiles.size());
  for (size_t i = 0; i < tiles.size(); ++i) byTop[i] = i;
  std::stable_sort(byTop.begin(), byTop.end(), [&](size_t a, size_t b) { return tiles[a].y0 < tiles[b].y0; });
  std::map<size_t, FrameImage> crossing;  // decoded tiles by index, while strips cross them
  size_t next = 0;
  int top = 0;
  for (const int bottom : stripEnds(tiles, height)) {
    for (; next < byTop.size() && tiles[byTop[next]].y0 < bottom; ++next) {
      Tile& tile = tiles[byTop[next]];
      const ChunkRef& ref = lease.inputs(tile.input);
      FrameImage image = decodeExr(tile.bytes ? *tile.bytes : fetch(ref), labelOf(ref));
      tile.bytes.reset();
      if (const std::string bad = image.firstNonFinite(); !bad.empty())
        throw BadInput(labelOf(ref) + " holds a non-finite value (" + bad + "): not pasted into the frame");
      crossing.emplace(byTop[next], std::move(image));
    }
    FrameImage strip(width, bottom - top);
    for (const std::string& name : channels) strip.addChannel(name);
    for (const auto& [index, image] : crossing) {
      const Tile& tile = tiles[index];
      const int from = std::max(top, tile.y0), to = std::min(bottom, tile.y1);
      if (from < to) strip.paste(image.crop(0, from - tile.y0, image.width(), to - from), tile.x0, from - top);
    }
    writer.write(strip);
    std::erase_if(crossing, [&](const auto& entry) { return tiles[entry.first].y1 <= bottom; });
    top = bottom;
    progress = 0.5 + 0.5 * static_cast<double>(bottom) / static_cast<double>(height);
  }
  writer.finish();
}

}  // namespace pathfarm::farm
