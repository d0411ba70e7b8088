#include "worker/filter_inputs.h"

#include <algorithm>
#include <map>
#include <memory>
#include <set>
#include <stdexcept>
#include <utility>

#include "postproc/filters/component_upsampler.h"
#include "postproc/filters/direct_emission.h"
#include "worker/failure_class.h"

namespace pathfarm::farm {

const FrameImage& TaskInput::image() const {
  if (!frame && decode) {
    frame = decode();
    decode = nullptr;
  }
  if (!frame) throw std::logic_error("a task input was read after it was taken");
  return *frame;
}

FrameImage TaskInput::part(const InputPart& wanted) const {
  return !frame && decodePart ? decodePart(wanted) : partOf(image(), wanted);
}

bool isFrameWideChannel(const std::string& name) {
  return std::count(name.begin(), name.end(), '.') <= 1;
}

FrameImage partOf(const FrameImage& frame, const InputPart& wanted) {
  const int endRow = wanted.endRow > 0 ? wanted.endRow : frame.height();
  if (wanted.firstRow < 0 || endRow > frame.height() || wanted.firstRow >= endRow)
    throw BadInput("rows " + std::to_string(wanted.firstRow) + " to " + std::to_string(endRow) +
                   " of a frame of " + std::to_string(frame.height()) + " rows");
  const size_t first = static_cast<size_t>(wanted.firstRow) * static_cast<size_t>(frame.width());
  const size_t end = static_cast<size_t>(endRow) * static_cast<size_t>(frame.width());
  FrameImage kept(frame.width(), endRow - wanted.firstRow);
  for (const std::string& name : frame.channelNames()) {
    if (wanted.keep && !wanted.keep(name)) continue;
    const std::vector<float>& values = frame.channel(name);
    kept.addChannel(name).assign(values.begin() + static_cast<ptrdiff_t>(first),
                                 values.begin() + static_cast<ptrdiff_t>(end));
  }
  kept.attributes() = frame.attributes();
  return kept;
}

ChannelFilter halfInEvery(const std::vector<TaskInput*>& inputs) {
  std::map<std::string, size_t> inputsHolding;
  for (const TaskInput* input : inputs)
    if (input->halfChannels)
      for (const std::string& name : input->halfChannels()) ++inputsHolding[name];
  std::set<std::string> half;
  for (const auto& [name, count] : inputsHolding)
    if (count == inputs.size()) half.insert(name);
  return [half = std::move(half)](const std::string& name) { return half.count(name) > 0; };
}

FrameImage TaskInput::take() {
  image();
  const std::shared_ptr<FrameImage> held = std::move(frame);
  if (held.use_count() > 1) return *held;
  return std::move(*held);
}

FrameImage reducedWithoutLight(const TaskInput& input, int width, int height, int factor, const InputPart& rows) {
  const int first = rows.firstRow, end = rows.endRow > 0 ? rows.endRow : height;
  if (first % factor != 0 || end % factor != 0 || first < 0 || end > height || first >= end)
    throw BadInput("rows " + std::to_string(first) + " to " + std::to_string(end) + " of a render of " +
                   std::to_string(height) + " rows are not whole blocks of " + std::to_string(factor));
  // Rows read at a time: whole blocks.
  const int stripRows = std::max(64 / factor, 1) * factor;
  FrameImage reduced(width / factor, (end - first) / factor);
  for (int y = first; y < end; y += stripRows) {
    FrameImage strip = input.part({rows.keep, y, std::min(end, y + stripRows)});
    if (strip.width() != width) throw BadInput("a render to reduce is not " + std::to_string(width) + " pixels wide");
    takeDirectEmission(strip);
    const FrameImage low = boxDownsample(strip, factor);
    reduced.attributes() = low.attributes();
    reduced.paste(low, 0, (y - first) / factor);
  }
  return reduced;
}

void pasteFiltered(const FrameImage& filtered, const std::string& record, FrameImage& frame) {
  frame.paste(filtered, 0, 0);
  for (const auto& [key, value] : filtered.attributes())
    if (key.rfind(record, 0) == 0) frame.attributes()[key] = value;
}

const TaskInput& findInput(const std::vector<TaskInput>& inputs, const std::function<bool(const TaskInput&)>& matches,
                           const std::string& what) {
  const auto found = std::find_if(inputs.begin(), inputs.end(), matches);
  if (found == inputs.end()) throw BadInput("the task lacks an input: " + what);
  return *found;
}

const TaskInput& inputOf(const std::vector<TaskInput>& inputs, TaskKind kind, int64_t frame) {
  return findInput(
      inputs, [&](const TaskInput& input) { return input.kind == kind && input.params.frame() == frame; },
      TaskKind_Name(kind) + " of frame " + std::to_string(frame));
}

TaskInput& inputOf(std::vector<TaskInput>& inputs, TaskKind kind, int64_t frame) {
  return const_cast<TaskInput&>(inputOf(std::as_const(inputs), kind, frame));
}

TaskInput& filteredKeyframe(std::vector<TaskInput>& inputs, int64_t frame) {
  return const_cast<TaskInput&>(filteredKeyframe(std::as_const(inputs), frame));
}

const TaskInput& filteredKeyframe(const std::vector<TaskInput>& inputs, int64_t frame) {
  const auto upsampled = std::find_if(inputs.begin(), inputs.end(), [&](const TaskInput& input) {
    return input.kind == TASK_UPSAMPLE && input.params.frame() == frame;
  });
  return upsampled != inputs.end() ? *upsampled : inputOf(inputs, TASK_DENOISE, frame);
}

RowWindow rowsOf(const Lease& lease, const std::string& what) {
  const int width = lease.spec().width(), height = lease.spec().height();
  if (!lease.params().has_window()) return {0, height};
  const PixelWindow& w = lease.params().window();
  if (w.x0() != 0 || w.x1() != width || w.y0() < 0 || w.y1() > height || w.y0() >= w.y1())
    throw BadInput(what + " of frame " + std::to_string(lease.params().frame()) + " is not of whole rows of the frame");
  return {w.y0(), w.y1()};
}

JoinedWindows joinRowWindows(const Lease& lease, std::vector<TaskInput>& inputs, const std::string& what,
                             const std::function<void(const FrameImage&)>& check, TaskOutput& output,
                             JoinedFrame joined) {
  const int factor = joined.factor, width = lease.spec().width() / factor, height = lease.spec().height() / factor;
  const bool flagged = joined.flagged;
  const std::string label = "frame " + std::to_string(lease.params().frame());
  const std::string refused = "the windows' " + what + " of " + label;
  std::vector<TaskInput*> windows;
  for (TaskInput& input : inputs) {
    if (input.kind != lease.kind() || !input.params.has_window() || input.params.frame() != lease.params().frame())
      throw BadInput("the join of " + label + " takes its windows' " + what + " and nothing else");
    windows.push_back(&input);
  }
  std::sort(windows.begin(), windows.end(),
            [](const TaskInput* a, const TaskInput* b) { return a->params.window().y0() < b->params.window().y0(); });
  JoinedWindows read;
  read.mask.assign(static_cast<size_t>(width) * static_cast<size_t>(height), 0);
  int covered = 0;  // rows 0 .. covered - 1 are the windows' so far
  for (const TaskInput* window : windows) {
    const PixelWindow& w = window->params.window();
    const FrameImage flags =
        window->part({[flagged](const std::string& name) { return flagged && name == "rerender.Y"; }});
    const int first = w.y0() / factor, end = w.y1() / factor;
    if (w.x0() != 0 || w.x1() != width * factor || w.y0() != covered * factor || w.y1() % factor != 0 ||
        end > height || end <= first || flags.width() != width || flags.height() != end - first)
      throw BadInput(refused + " do not cover the frame's rows once each, in place");
    covered = end;
    read.attributes.push_back(flags.attributes());
    if (!flagged) continue;
    const std::vector<float>& rows = channelOf(flags, "rerender.Y", refused);
    std::transform(rows.begin(), rows.end(), read.mask.begin() + static_cast<ptrdiff_t>(first) * width,
                   [](float value) { return static_cast<uint8_t>(value > 0.5f ? 1 : 0); });
  }
  if (covered != height) throw BadInput(refused + " do not cover the frame's rows once each, in place");
  output.joinedHeight = height;
  // The windows' values as they hold them: half floats where every window has them so.
  output.halfChannels = halfInEvery(windows);
  auto channels = std::make_shared<std::vector<std::string>>();
  for (TaskInput* window : windows)
    output.rowWindows.push_back([window, channels, check, refused] {
      FrameImage rows = window->take();
      if (check) check(rows);
      if (channels->empty()) *channels = rows.channelNames();
      if (rows.channelNames() != *channels) throw BadInput(refused + " have different channels");
      return rows;
    });
  return read;
}

std::map<std::string, std::string> summedCounts(const JoinedWindows& windows, const std::vector<std::string>& names,
                                                const std::string& what) {
  std::map<std::string, std::string> sums;
  for (const std::string& name : names) {
    size_t sum = 0;
    for (const auto& attributes : windows.attributes) {
      const auto found = attributes.find(name);
      const std::string text = found == attributes.end() ? "" : found->second;
      if (text.empty() || text.size() > 18 || !std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; }))
        throw BadInput("a window of " + what + " has " + name + " \"" + text + "\", not a count");
      sum += std::stoull(text);
    }
    sums[name] = std::to_string(sum);
  }
  return sums;
}

void addJoinedAttributes(TaskOutput& output, std::map<std::string, std::string> attributes) {
  if (output.rowWindows.empty()) throw std::logic_error("addJoinedAttributes: the output joins no windows");
  output.rowWindows.front() = [first = std::move(output.rowWindows.front()), added = std::move(attributes)] {
    FrameImage rows = first();
    for (const auto& [key, value] : added) rows.attributes()[key] = value;
    return rows;
  };
}

bool joinsWindows(const Lease& lease, const std::vector<TaskInput>& inputs) {
  return !lease.params().has_window() &&
         std::any_of(inputs.begin(), inputs.end(), [&](const TaskInput& input) { return input.kind == lease.kind(); });
}

TaskOutput joinedWithRerender(const Lease& lease, std::vector<TaskInput>& inputs, const std::string& what) {
  TaskOutput output;
  const std::vector<uint8_t> mask = joinRowWindows(lease, inputs, what, [](const FrameImage&) {}, output).mask;
  requestRerender(lease.spec(), lease.params().frame(), mask, output);
  return output;
}

void writeMotionField(FrameImage& image, const std::string& name, const MotionField& field) {
  image.addChannel(name + ".X") = field.x;
  image.addChannel(name + ".Y") = field.y;
  std::vector<float>& valid = image.addChannel(name + ".valid");
  if (field.valid.empty()) {
    std::fill(valid.begin(), valid.end(), 1.0f);
  } else {
    valid = field.valid;
  }
}

MotionField readMotionField(const FrameImage& image, const std::string& name) {
  MotionField field;
  field.width = image.width();
  field.height = image.height();
  field.x = image.channel(name + ".X");
  field.y = image.channel(name + ".Y");
  field.valid = image.channel(name + ".valid");
  return field;
}

void requestRerender(const ShotSpec& spec, int64_t frame, const std::vector<uint8_t>& mask, TaskOutput& output) {
  const int width = spec.width(), height = spec.height(), tile = spec.tile(), spp = rerenderSppOf(spec);
  if (mask.size() != static_cast<size_t>(width) * static_cast<size_t>(height))
    throw BadInput("the re-render mask does not have the shot's resolution");
  size_t flagged = 0;
  for (int y0 = 0; y0 < height; y0 += tile) {
    for (int x0 = 0; x0 < width; x0 += tile) {
      const int x1 = std::min(x0 + tile, width), y1 = std::min(y0 + tile, height);
      std::string pixels;
      size_t inTile = 0;
      for (int y = y0; y < y1; ++y) {
        for (int x = x0; x < x1; ++x) {
          const bool flag = mask[static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)] != 0;
          pixels.push_back(flag ? 1 : 0);
          inTile += flag;
        }
      }
      if (inTile == 0) continue;
      flagged += inTile;
      TaskParams& params = output.followUps.emplace_back();
      params.set_frame(frame);
      params.set_role(ROLE_RERENDER);
      params.set_spp(spp);
      params.set_pixel_mask(pixels);
      PixelWindow* window = params.mutable_window();
      window->set_x0(x0);
      window->set_y0(y0);
      window->set_x1(x1);
      window->set_y1(y1);
    }
  }
  output.metrics["rerender_pixels"] = static_cast<double>(flagged);
  output.metrics["pixels"] = static_cast<double>(mask.size());
}

}  // namespace pathfarm::farm
