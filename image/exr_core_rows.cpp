#include "image/exr_core_rows.h"

#include <OpenEXR/openexr.h>

#include <algorithm>
#include <cstring>
#include <map>
#include <stdexcept>

namespace pathfarm {
namespace {

// The last message OpenEXRCore reported on this thread: its error codes alone say little
// ("corrupt chunk"), the handler's message says where.
thread_local std::string lastMessage;

void keepMessage(exr_const_context_t, exr_result_t code, const char* message) {
  lastMessage = std::string(exr_get_error_code_as_string(code)) + ": " + (message ? message : "");
}

void check(exr_result_t result, const char* what) {
  if (result == EXR_ERR_SUCCESS) return;
  const std::string message = lastMessage.empty() ? exr_get_default_error_message(result) : lastMessage;
  lastMessage.clear();
  throw std::runtime_error(std::string(what) + ": " + message);
}

int64_t readBytes(exr_const_context_t, void* userdata, void* buffer, uint64_t size, uint64_t offset,
                  exr_stream_error_func_ptr_t) {
  const auto* bytes = static_cast<const std::string_view*>(userdata);
  if (offset >= bytes->size()) return 0;
  const size_t n = std::min<uint64_t>(size, bytes->size() - offset);
  std::memcpy(buffer, bytes->data() + offset, n);
  return static_cast<int64_t>(n);
}

int64_t sizeOfBytes(exr_const_context_t, void* userdata) {
  return static_cast<int64_t>(static_cast<const std::string_view*>(userdata)->size());
}

}  // namespace

// An open OpenEXRCore context, finished when it goes, and the decoding pipeline over the
// chunks of its part 0.
struct ExrCoreRows::Reader {
  std::string_view bytes;
  exr_context_t context = nullptr;
  exr_decode_pipeline_t pipeline = EXR_DECODE_PIPELINE_INITIALIZER;
  bool decoding = false;
  size_t width = 0;
  int32_t firstRow = 0, chunkRows = 0;
  std::vector<size_t> nameOf;  // per channel of the file: the index of its name, or npos
  std::vector<float> spare;    // a chunk the rows cut, unpacked whole

  ~Reader() {
    if (decoding) exr_decoding_destroy(context, &pipeline);
    if (context) exr_finish(&context);
  }

  // Unpacks `chunk` with its row 0 of file channel c at targets[c] (null: skipped).
  void unpack(const exr_chunk_info_t& chunk, const std::vector<float*>& targets) {
    const bool first = !decoding;
    decoding = true;  // a pipeline that failed to start is destroyed as well
    check(first ? exr_decoding_initialize(context, 0, &chunk, &pipeline)
                : exr_decoding_update(context, 0, &chunk, &pipeline),
          "decode");
    for (int c = 0; c < pipeline.channel_count; ++c) {
      exr_coding_channel_info_t& channel = pipeline.channels[c];
      channel.decode_to_ptr = reinterpret_cast<uint8_t*>(targets[static_cast<size_t>(c)]);
      channel.user_pixel_stride = sizeof(float);
      channel.user_line_stride = static_cast<int32_t>(width * sizeof(float));
      channel.user_bytes_per_element = sizeof(float);
      channel.user_data_type = EXR_PIXEL_FLOAT;
    }
    if (first) check(exr_decoding_choose_default_routines(context, 0, &pipeline), "decode");
    check(exr_decoding_run(context, 0, &pipeline), "decode");
  }
};

ExrCoreRows::ExrCoreRows(const ExrBytes& source, const std::vector<std::string>& names)
    : reader_(std::make_unique<Reader>()) {
  lastMessage.clear();
  Reader& r = *reader_;
  r.bytes = source.bytes;
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  init.error_handler_fn = keepMessage;
  if (source.file) {
    check(exr_start_read(&r.context, source.file->c_str(), &init), "open");
  } else {
    init.user_data = &r.bytes;
    init.read_fn = readBytes;
    init.size_fn = sizeOfBytes;
    check(exr_start_read(&r.context, "memory", &init), "open");
  }
  int parts = 0;
  exr_storage_t storage{};
  exr_compression_t compression{};
  check(exr_get_count(r.context, &parts), "read the parts");
  if (parts != 1 || exr_get_storage(r.context, 0, &storage) != EXR_ERR_SUCCESS || storage != EXR_STORAGE_SCANLINE)
    return;
  // The farm's codecs (RLE and ZIP) and none; OpenEXRCore 3.1 unpacks PIZ slower than
  // Imf::InputFile (bench/chunk_compression.cpp), and the lossy ones are other tools'.
  check(exr_get_compression(r.context, 0, &compression), "read the compression");
  if (compression != EXR_COMPRESSION_NONE && compression != EXR_COMPRESSION_RLE &&
      compression != EXR_COMPRESSION_ZIPS && compression != EXR_COMPRESSION_ZIP)
    return;
  const exr_attr_chlist_t* channels = nullptr;
  exr_attr_box2i_t window{};
  check(exr_get_channels(r.context, 0, &channels), "read the channels");
  check(exr_get_data_window(r.context, 0, &window), "read the data window");
  check(exr_get_scanlines_per_chunk(r.context, 0, &r.chunkRows), "read the chunk size");
  std::map<std::string_view, size_t> wanted;
  for (size_t i = 0; i < names.size(); ++i) wanted[names[i]] = i;
  for (int c = 0; c < channels->num_channels; ++c) {
    const exr_attr_chlist_entry_t& channel = channels->entries[c];
    const auto name = wanted.find(std::string_view(channel.name.str, static_cast<size_t>(channel.name.length)));
    if (name == wanted.end()) {
      r.nameOf.push_back(std::string::npos);
      continue;
    }
    // Half channels are unpacked into floats (the farm's intermediate chunks, exr_io.h).
    const bool floats = channel.pixel_type == EXR_PIXEL_FLOAT || channel.pixel_type == EXR_PIXEL_HALF;
    if (!floats || channel.x_sampling != 1 || channel.y_sampling != 1) return;
    r.nameOf.push_back(name->second);
    wanted.erase(name);
  }
  if (!wanted.empty()) throw std::runtime_error("no channel \"" + std::string(wanted.begin()->first) + "\"");
  r.width = static_cast<size_t>(int64_t{window.max.x} - window.min.x + 1);
  r.firstRow = window.min.y;
  usable_ = r.chunkRows > 0;
}

ExrCoreRows::~ExrCoreRows() = default;

void ExrCoreRows::read(const std::vector<float*>& planes, int from, int to) {
  if (!usable_) throw std::logic_error("ExrCoreRows::read of an EXR it does not handle");
  Reader& r = *reader_;
  const size_t channels = r.nameOf.size();
  std::vector<float*> targets(channels);
  for (int row = from - from % r.chunkRows; row < to; row += r.chunkRows) {
    exr_chunk_info_t chunk{};
    check(exr_read_scanline_chunk_info(r.context, 0, r.firstRow + row, &chunk), "read a chunk");
    const int first = chunk.start_y - r.firstRow, end = first + chunk.height;
    // A chunk inside the rows is unpacked in place; one the rows cut, whole beside them.
    const bool inside = first >= from && end <= to;
    const size_t chunkFloats = r.width * static_cast<size_t>(chunk.height);
    if (!inside) r.spare.resize(chunkFloats * channels);
    for (size_t c = 0; c < channels; ++c) {
      if (r.nameOf[c] == std::string::npos) targets[c] = nullptr;
      else if (inside) targets[c] = planes[r.nameOf[c]] + static_cast<size_t>(first - from) * r.width;
      else targets[c] = r.spare.data() + c * chunkFloats;
    }
    r.unpack(chunk, targets);
    if (inside) continue;
    const int keptFirst = std::max(first, from), keptEnd = std::min(end, to);
    for (size_t c = 0; c < channels; ++c) {
      if (!targets[c]) continue;
      std::memcpy(planes[r.nameOf[c]] + static_cast<size_t>(keptFirst - from) * r.width,
                  targets[c] + static_cast<size_t>(keptFirst - first) * r.width,
                  static_cast<size_t>(keptEnd - keptFirst) * r.width * sizeof(float));
    }
  }
}

}  // namespace pathfarm
