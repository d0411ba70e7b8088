#include "postproc/filters/component_upsampler.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "image/luminance.h"
#include "image/size_text.h"
#include "postproc/filters/decomposed_frame.h"
#include "renderer/decomposition/effective_irradiance.h"

namespace pathfarm {
namespace {

constexpr const char* kDecompositionAttribute = "pathfarm.decomposition";

// The channel suffixes of the data contract's buffers (docs/decomposition.md).
const std::vector<std::string>* knownChannels(const std::string& buffer) {
  static const std::map<std::string, std::vector<std::string>> table = {
      {"color", {"R", "G", "B"}},      {"variance", {"R", "G", "B"}},    {"reflectance", {"R", "G", "B"}},
      {"irradiance", {"R", "G", "B"}}, {"emission", {"R", "G", "B"}},    {"normal", {"X", "Y", "Z"}},
      {"uv", {"X", "Y"}},              {"motion", {"X", "Y"}},           {"motion_back", {"X", "Y"}},
      {"depth", {"Z"}},                {"objectid", {"Y"}},              {"primid", {"Y"}},
      {"motion_valid", {"Y"}},         {"coverage", {"Y"}},
  };
  const auto it = table.find(buffer);
  return it == table.end() ? nullptr : &it->second;
}

// The channels of "<component>.<buffer>.*" in `frame`: the known suffixes (each must exist)
// or, for other buffers, every channel with that prefix in frame order (at least one).
// `what` names the frame with its verb ("low-resolution frame has").
std::vector<std::string> bufferChannels(const FrameImage& frame, const std::string& component,
                                        const std::string& buffer, const std::string& what) {
  const std::string prefix = component + "." + buffer + ".";
  std::vector<std::string> names;
  if (const std::vector<std::string>* suffixes = knownChannels(buffer)) {
    for (const std::string& suffix : *suffixes) {
      if (!frame.hasChannel(prefix + suffix))
        throw std::invalid_argument("upsampleFrame: the " + what + " no channel \"" + prefix + suffix +
                                    "\" (component \"" + component + "\")");
      names.push_back(prefix + suffix);
    }
    return names;
  }
  for (const std::string& name : frame.channelNames())
    if (name.compare(0, prefix.size(), prefix) == 0) names.push_back(name);
  if (names.empty())
    throw std::invalid_argument("upsampleFrame: the " + what + " no channel \"" + prefix + "*\" (component \"" +
                                component + "\")");
  return names;
}

std::string describeSettings(const UpsampleSettings& settings) {
  std::ostringstream text;
  text << "guided factor=" << settings.guided.factor << " radius=" << settings.guided.radius
       << " epsilon=" << settings.guided.epsilon << " guide=";
  for (size_t i = 0; i < settings.guideBuffers.size(); ++i) text << (i ? "+" : "") << settings.guideBuffers[i];
  return text.str();
}

// "<prefix>.<buffer>.<channel>" or "<buffer>.<channel>" (prefix empty) or a bare name.
struct ChannelName {
  std::string prefix, buffer, channel;
};

ChannelName splitChannel(const std::string& name) {
  ChannelName parts;
  const size_t last = name.rfind('.');
  if (last == std::string::npos) {
    parts.channel = name;
    return parts;
  }
  parts.channel = name.substr(last + 1);
  const size_t before = name.rfind('.', last - 1);
  if (last == 0 || before == std::string::npos) {
    parts.buffer = name.substr(0, last);
  } else {
    parts.prefix = name.substr(0, before);
    parts.buffer = name.substr(before + 1, last - before - 1);
  }
  return parts;
}

std::vector<std::string> componentsOf(const FrameImage& frame) {
  std::vector<std::string> names = decompositionComponents(frame);
  if (names.empty())
    throw std::invalid_argument(std::string("upsampleFrame: the low-resolution frame has no \"") +
                                kDecompositionAttribute + "\" attribute (is it a decomposed render?)");
  return names;
}

// A usable factor and guide, and features the factor times larger than `low`.
void checkSizes(const FrameImage& low, const FrameImage& highFeatures, const UpsampleSettings& settings) {
  const int factor = settings.guided.factor;
  if (factor < 1) throw std::invalid_argument("upsampleFrame: the factor must be at least 1, not " + std::to_string(factor));
  if (settings.guideBuffers.empty()) throw std::invalid_argument("upsampleFrame: no guide buffer is set");
  if (static_cast<long long>(low.width()) * factor != highFeatures.width() ||
      static_cast<long long>(low.height()) * factor != highFeatures.height())
    throw std::invalid_argument("upsampleFrame: a " + sizeText(low.width(), low.height()) + " frame upsampled by " +
                                std::to_string(factor) + " needs " +
                                sizeText(low.width() * factor, low.height() * factor) +
                                " features, not " + sizeText(highFeatures.width(), highFeatures.height()));
}

// The features either say no decomposition or the low-resolution frame's.
void checkSameDecomposition(const FrameImage& low, const FrameImage& highFeatures) {
  const auto highDecomposition = highFeatures.attributes().find(kDecompositionAttribute);
  if (highDecomposition != highFeatures.attributes().end() &&
      highDecomposition->second != low.attributes().at(kDecompositionAttribute))
    throw std::invalid_argument("upsampleFrame: the features' decomposition \"" + highDecomposition->second +
                                "\" is not the low-resolution frame's \"" +
                                low.attributes().at(kDecompositionAttribute) + "\"");
}

// The channels the upsampling of one component reads.
struct ComponentChannels {
  std::vector<std::string> irradiance, reflectance, guide;
};

ComponentChannels componentChannels(const FrameImage& low, const FrameImage& highFeatures, const std::string& c,
                                    const UpsampleSettings& settings) {
  ComponentChannels channels;
  channels.irradiance = bufferChannels(low, c, "irradiance", "low-resolution frame has");
  channels.reflectance = bufferChannels(highFeatures, c, "reflectance", "full-resolution features have");
  for (const std::string& buffer : settings.guideBuffers) {
    const std::vector<std::string> names = bufferChannels(highFeatures, c, buffer, "full-resolution features have");
    channels.guide.insert(channels.guide.end(), names.begin(), names.end());
  }
  return channels;
}

// Where no sample of the full-resolution render found the component (its normal is
// zero), there is none of it: the fit must not spill its neighbours' light there.
void clearWhereNotFound(GuidedUpsampleResult& up, const FrameImage& highFeatures, const std::string& c) {
  if (!highFeatures.hasChannel(c + ".normal.X")) return;
  const std::vector<float>&nx = highFeatures.channel(c + ".normal.X"), &ny = highFeatures.channel(c + ".normal.Y"),
  &nz = highFeatures.channel(c + ".normal.Z");
  for (size_t i = 0; i < nx.size(); ++i) {
    if (nx[i] != 0.0f || ny[i] != 0.0f || nz[i] != 0.0f) continue;
    for (std::vector<float>& channel : up.image.channels) channel[i] = 0.0f;
    up.rerender[i] = 0.0f;
  }
}

// Component c's irradiance upsampled by the guided filter under its features.
GuidedUpsampleResult upsampledIrradiance(const FrameImage& low, const FrameImage& highFeatures, const std::string& c,
                                         const ComponentChannels& channels, const GuidedUpsampleSettings& settings) {
  Planes lowIrradiance(low.width(), low.height(), 0);
  for (const std::string& name : channels.irradiance) lowIrradiance.channels.push_back(low.channel(name));
  // With coverage in both frames, the fit works on the light per covered area. The
  // irradiance carries the component's share of each pixel; at a silhouette the
  // full-resolution pixel's share is not the low-resolution block's, so the block's light
  // spread over an edge pixel would be too bright where the component covers little of it.
  const std::vector<float>* lowCoverage = filterCoverage(low, c);
  const std::vector<float>* highCoverage = filterCoverage(highFeatures, c);
  const bool byCoverage = lowCoverage != nullptr && highCoverage != nullptr;
  if (byCoverage)
    for (std::vector<float>& channel : lowIrradiance.channels)
      for (size_t i = 0; i < channel.size(); ++i) channel[i] = perCoveredArea(channel[i], (*lowCoverage)[i]);
  Planes guide(highFeatures.width(), highFeatures.height(), 0);
  for (const std::string& name : channels.guide) guide.channels.push_back(highFeatures.channel(name));

  GuidedUpsampleResult up = guidedUpsample(lowIrradiance, guide, settings);
  if (byCoverage) {
    for (size_t i = 0; i < highCoverage->size(); ++i) {
      const float share = coverageShare((*highCoverage)[i]);
      for (std::vector<float>& channel : up.image.channels) channel[i] *= share;
      up.deficit[i] *= share;
    }
  }
  clearWhereNotFound(up, highFeatures, c);
  return up;
}

// Adds component c's color (the upsampled irradiance modulated by the full-resolution
// reflectance) and irradiance to `out`, the color to its beauty, and the color the
// clamping lost to `clamped`.
void addComponent(FrameImage& out, std::vector<float>& clamped, const FrameImage& highFeatures, const std::string& c,
                  const ComponentChannels& channels, const GuidedUpsampleResult& up) {
  // Green, the channel luminance weighs most, scales the lost irradiance to color.
  const std::vector<float>& reflectanceG = highFeatures.channel(channels.reflectance[1]);
  for (size_t i = 0; i < clamped.size(); ++i)
    if (up.rerender[i] != 0.0f) clamped[i] += modulateIrradiance(up.deficit[i], reflectanceG[i]);
  for (int j = 0; j < 3; ++j) {
    const std::vector<float>& irradiance = up.image.channels[static_cast<size_t>(j)];
    const std::vector<float>& reflectance = highFeatures.channel(channels.reflectance[static_cast<size_t>(j)]);
    std::vector<float>& color = out.addChannel(c + ".color." + kRgbChannels[j]);
    std::vector<float>& beauty = out.channel(kRgbChannels[j]);
    for (size_t i = 0; i < color.size(); ++i) {
      color[i] = modulateIrradiance(irradiance[i], reflectance[i]);
      beauty[i] += color[i];
    }
    out.addChannel(c + ".irradiance." + kRgbChannels[j]) = irradiance;
  }
}

// `rerender.Y`: 1 where the color lost to clamping is significant against the beauty.
void addRerenderFlags(FrameImage& out, const std::vector<float>& clamped, float significance) {
  std::vector<float> rerender(out.pixelCount(), 0.0f);
  size_t rerenderPixels = 0;
  const std::vector<float>&r = out.channel("R"), &g = out.channel("G"), &b = out.channel("B");
  for (size_t i = 0; i < rerender.size(); ++i) {
    const float beautyLuminance = luminance(r[i], g[i], b[i]);
    if (clamped[i] > significance * std::max(beautyLuminance, 1e-6f)) {
      rerender[i] = 1.0f;
      ++rerenderPixels;
    }
  }
  out.addChannel("rerender.Y") = std::move(rerender);
  out.attributes()["pathfarm.rerender_pixels"] = std::to_string(rerenderPixels);
}

}  // namespace

FrameImage upsampleFrame(const FrameImage& low, const FrameImage& highFeatures, const UpsampleSettings& settings) {
  checkSizes(low, highFeatures, settings);
  const std::vector<std::string> components = componentsOf(low);
  checkSameDecomposition(low, highFeatures);
  // Every channel is checked before any work is done.
  std::vector<ComponentChannels> channels;
  for (const std::string& c : components) channels.push_back(componentChannels(low, highFeatures, c, settings));

  FrameImage out(highFeatures.width(), highFeatures.height());
  out.attributes() = low.attributes();
  for (const char* name : kRgbChannels) out.addChannel(name);
  std::vector<float> clamped(out.pixelCount(), 0.0f);  // color lost to clamping, summed over components
  for (size_t k = 0; k < components.size(); ++k) {
    const GuidedUpsampleResult up = upsampledIrradiance(low, highFeatures, components[k], channels[k], settings.guided);
    addComponent(out, clamped, highFeatures, components[k], channels[k], up);
  }
  addRerenderFlags(out, clamped, settings.significance);
  out.attributes()["pathfarm.upsample"] = describeSettings(settings);
  return out;
}

FrameImage boxDownsample(const FrameImage& high, int factor) {
  if (factor < 1) throw std::invalid_argument("boxDownsample: the factor must be at least 1, not " + std::to_string(factor));
  if (high.width() % factor != 0 || high.height() % factor != 0)
    throw std::invalid_argument("boxDownsample: a " + sizeText(high.width(), high.height()) +
                                " frame is not a multiple of the factor " + std::to_string(factor));
  const int width = high.width() / factor, height = high.height() / factor;
  FrameImage low(width, height);
  low.attributes() = high.attributes();
  const double inverseArea = 1.0 / (static_cast<double>(factor) * factor);

  enum class Rule { Mean, Variance, Motion, TopLeft, Maximum };
  for (const std::string& name : high.channelNames()) {
    const ChannelName parts = splitChannel(name);
    Rule rule = Rule::Mean;
    if (parts.buffer == "variance") rule = Rule::Variance;
    else if (parts.buffer == "motion" || parts.buffer == "motion_back") rule = Rule::Motion;
    else if (parts.buffer == "objectid" || parts.buffer == "primid") rule = Rule::TopLeft;
    else if (parts.buffer == "silhouette" || parts.buffer == "motion_valid") rule = Rule::Maximum;

    const std::vector<float>& source = high.channel(name);
    std::vector<float>& target = low.addChannel(name);
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        const size_t corner = static_cast<size_t>(y) * factor * high.width() + static_cast<size_t>(x) * factor;
        float& value = target[static_cast<size_t>(y) * width + x];
        if (rule == Rule::TopLeft) {
          value = source[corner];
          continue;
        }
        double sum = 0.0;
        float maximum = source[corner];
        for (int dy = 0; dy < factor; ++dy)
          for (int dx = 0; dx < factor; ++dx) {
            const float v = source[corner + static_cast<size_t>(dy) * high.width() + dx];
            sum += v;
            maximum = std::max(maximum, v);
          }
        double mean = sum * inverseArea;
        if (rule == Rule::Variance) mean *= inverseArea;
        if (rule == Rule::Motion) mean /= factor;
        value = rule == Rule::Maximum ? maximum : static_cast<float>(mean);
      }
  }

  // A reflectance is a mean over the samples that reached the component's surface, so a
  // block's is weighed by each pixel's coverage (a pixel the component does not cover has
  // reflectance 0, which is no albedo).
  for (const std::string& name : high.channelNames()) {
    const ChannelName parts = splitChannel(name);
    const std::string coverageName = parts.prefix + ".coverage.Y";
    if (parts.prefix.empty() || parts.buffer != "reflectance" || !high.hasChannel(coverageName)) continue;
    const std::vector<float>& source = high.channel(name);
    const std::vector<float>& coverage = high.channel(coverageName);
    std::vector<float>& target = low.channel(name);
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        const size_t corner = static_cast<size_t>(y) * factor * high.width() + static_cast<size_t>(x) * factor;
        double weighted = 0.0, covered = 0.0;
        for (int dy = 0; dy < factor; ++dy)
          for (int dx = 0; dx < factor; ++dx) {
            const size_t i = corner + static_cast<size_t>(dy) * high.width() + dx;
            weighted += static_cast<double>(source[i]) * coverage[i];
            covered += coverage[i];
          }
        if (covered > 0.0) target[static_cast<size_t>(y) * width + x] = static_cast<float>(weighted / covered);
      }
  }

  // Derived buffers, from the block means as the renderer derives them per pixel.
  for (const std::string& name : high.channelNames()) {
    const ChannelName parts = splitChannel(name);
    if (parts.prefix.empty()) continue;
    if (parts.buffer == "irradiance") {
      const std::string color = parts.prefix + ".color." + parts.channel;
      const std::string reflectance = parts.prefix + ".reflectance." + parts.channel;
      if (!low.hasChannel(color) || !low.hasChannel(reflectance)) continue;
      const std::vector<float>& c = low.channel(color);
      const std::vector<float>& r = low.channel(reflectance);
      std::vector<float>& irradiance = low.channel(name);
      for (size_t i = 0; i < irradiance.size(); ++i) irradiance[i] = effectiveIrradiance(c[i], r[i]);
    } else if (parts.buffer == "normal" && parts.channel == "X") {
      const std::string base = parts.prefix + ".normal.";
      if (!low.hasChannel(base + "Y") || !low.hasChannel(base + "Z")) continue;
      std::vector<float>& nx = low.channel(base + "X");
      std::vector<float>& ny = low.channel(base + "Y");
      std::vector<float>& nz = low.channel(base + "Z");
      for (size_t i = 0; i < nx.size(); ++i) {
        const double length = std::sqrt(static_cast<double>(nx[i]) * nx[i] + static_cast<double>(ny[i]) * ny[i] +
                                        static_cast<double>(nz[i]) * nz[i]);
        if (!(length > 0.0)) continue;
        nx[i] = static_cast<float>(nx[i] / length);
        ny[i] = static_cast<float>(ny[i] / length);
        nz[i] = static_cast<float>(nz[i] / length);
      }
    }
  }
  return low;
}

}  // namespace pathfarm
