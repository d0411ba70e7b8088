#include "renderer/scene/texture.h"

#include <stb_image.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <string>
#include <utility>

#include "renderer/scene/scene_inputs.h"

namespace pathfarm {

namespace {

// The sRGB electro-optical transfer function (IEC 61966-2-1), evaluated in double.
double srgbToLinear(double c) {
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

double decodeFraction(double c, TextureEncoding encoding) {
  return encoding == TextureEncoding::Srgb ? srgbToLinear(c) : c;
}

std::array<float, 256> make8BitTable(TextureEncoding encoding) {
  std::array<float, 256> t{};
  for (int i = 0; i < 256; ++i)
    t[static_cast<size_t>(i)] = static_cast<float>(decodeFraction(i / 255.0, encoding));
  return t;
}

const std::array<float, 256>& table8Bit(TextureEncoding encoding) {
  static const std::array<float, 256> srgb = make8BitTable(TextureEncoding::Srgb);
  static const std::array<float, 256> linear = make8BitTable(TextureEncoding::Linear);
  return encoding == TextureEncoding::Srgb ? srgb : linear;
}

[[noreturn]] void failLoad(const std::filesystem::path& file) {
  const char* reason = stbi_failure_reason();
  throw TextureError(file.string() + ": cannot load image (" +
                     (reason ? std::string(reason) : std::string("unknown reason")) + ")");
}

struct StbFree {
  void operator()(void* p) const { stbi_image_free(p); }
};

// Wraps i into [0, n).
int wrap(int i, int n) {
  const int r = i % n;
  return r < 0 ? r + n : r;
}

// The two texels a bilinear lookup blends along one axis, and the weight of the second.
struct AxisTexels {
  int i0, i1;
  float weight;
};

// `t` in texture coordinates along an axis of `n` texels, counted from the other end
// when `reversed` (rows run from v = 1 down). Coordinates are reduced to one period
// first, so huge or non-finite values cannot overflow the integer arithmetic.
AxisTexels axisTexels(float t, int n, TextureWrap mode, bool reversed) {
  if (!std::isfinite(t)) t = 0;
  if (mode == TextureWrap::Repeat) {
    const float f = t - std::floor(t);
    t = f < 1.0f ? f : 0.0f;
  } else if (mode == TextureWrap::Mirror) {
    const float f = t - 2 * std::floor(t / 2);  // [0, 2)
    t = f > 1 ? 2 - f : f;
  } else {
    t = std::clamp(t, 0.0f, 1.0f);
  }
  if (reversed) t = 1.0f - t;
  // Texel centres sit at (i + 0.5) / n.
  const float s = t * static_cast<float>(n) - 0.5f;
  const float sFloor = std::floor(s);
  const int i0 = static_cast<int>(sFloor);
  if (mode == TextureWrap::Repeat) return {wrap(i0, n), wrap(i0 + 1, n), s - sFloor};
  // Clamp and mirror hold the edge texel beyond the last centre.
  return {std::clamp(i0, 0, n - 1), std::clamp(i0 + 1, 0, n - 1), s - sFloor};
}

}  // namespace

ImageTexture::ImageTexture(int width, int height, std::vector<Rgb> texels)
    : width_(width), height_(height), texels_(std::move(texels)) {
  if (width <= 0 || height <= 0 ||
      texels_.size() != static_cast<size_t>(width) * static_cast<size_t>(height)) {
    throw TextureError("ImageTexture: " + std::to_string(texels_.size()) +
                       " texels do not make a " + std::to_string(width) + "x" +
                       std::to_string(height) + " image");
  }
}

ImageTexture ImageTexture::load(const std::filesystem::path& file, TextureEncoding encoding) {
  noteSceneInput(file);
  const std::string name = file.string();
  constexpr int kChannels = 3;
  int w = 0, h = 0, channelsInFile = 0;
  std::vector<Rgb> texels;

  if (stbi_is_hdr(name.c_str())) {
    // Radiance HDR and friends hold linear values already.
    std::unique_ptr<float, StbFree> data(
        stbi_loadf(name.c_str(), &w, &h, &channelsInFile, kChannels));
    if (!data) failLoad(file);
    const size_t n = static_cast<size_t>(w) * static_cast<size_t>(h);
    texels.resize(n);
    for (size_t i = 0; i < n; ++i) {
      const float* p = data.get() + i * kChannels;
      texels[i] = Rgb(p[0], p[1], p[2]);
    }
  } else if (stbi_is_16_bit(name.c_str())) {
    // 16-bit PNG: keep the extra precision.
    std::unique_ptr<stbi_us, StbFree> data(
        stbi_load_16(name.c_str(), &w, &h, &channelsInFile, kChannels));
    if (!data) failLoad(file);
    const size_t n = static_cast<size_t>(w) * static_cast<size_t>(h);
    texels.resize(n);
    auto decode = [&](stbi_us v) { return static_cast<float>(decodeFraction(v / 65535.0, encoding)); };
    for (size_t i = 0; i < n; ++i) {
      const stbi_us* p = data.get() + i * kChannels;
      texels[i] = Rgb(decode(p[0]), decode(p[1]), decode(p[2]));
    }
  } else {
    std::unique_ptr<stbi_uc, StbFree> data(
        stbi_load(name.c_str(), &w, &h, &channelsInFile, kChannels));
    if (!data) failLoad(file);
    const std::array<float, 256>& table = table8Bit(encoding);
    const size_t n = static_cast<size_t>(w) * static_cast<size_t>(h);
    texels.resize(n);
    for (size_t i = 0; i < n; ++i) {
      const stbi_uc* p = data.get() + i * kChannels;
      texels[i] = Rgb(table[p[0]], table[p[1]], table[p[2]]);
    }
  }
  if (w <= 0 || h <= 0) throw TextureError(file.string() + ": image has no pixels");
  return ImageTexture(w, h, std::move(texels));
}

ImageTexture ImageTexture::fromPixels(int width, int height, int channels, int bitsPerChannel,
                                      const unsigned char* data, bool srgb) {
  if (width <= 0 || height <= 0 || channels < 1 || channels > 4 || (bitsPerChannel != 8 && bitsPerChannel != 16))
    throw TextureError("unsupported pixel layout: " + std::to_string(width) + "x" + std::to_string(height) + ", " +
                       std::to_string(channels) + " channels of " + std::to_string(bitsPerChannel) + " bits");
  const std::array<float, 256>& table = table8Bit(TextureEncoding::Srgb);
  const size_t bytes = static_cast<size_t>(bitsPerChannel / 8);
  const auto value = [&](size_t index) -> float {
    if (bytes == 1) return srgb ? table[data[index]] : data[index] / 255.0f;
    const double v = (data[2 * index] | (data[2 * index + 1] << 8)) / 65535.0;
    return static_cast<float>(srgb ? srgbToLinear(v) : v);
  };
  const size_t n = static_cast<size_t>(width) * static_cast<size_t>(height);
  const size_t stride = static_cast<size_t>(channels);
  const bool grey = channels < 3;
  std::vector<Rgb> texels(n);
  for (size_t i = 0; i < n; ++i) {
    const size_t p = i * stride;
    texels[i] = grey ? Rgb(value(p)) : Rgb(value(p), value(p + 1), value(p + 2));
  }
  return ImageTexture(width, height, std::move(texels));
}

Rgb ImageTexture::texel(int x, int y) const {
  return texels_[static_cast<size_t>(y) * static_cast<size_t>(width_) + static_cast<size_t>(x)];
}

Rgb ImageTexture::average() const {
  Rgb sum;
  for (const Rgb& t : texels_) sum += t;
  return texels_.empty() ? Rgb() : sum / static_cast<float>(texels_.size());
}

Rgb ImageTexture::lookup(Vec2f uv) const {
  const AxisTexels x = axisTexels(uv.x, width_, wrapU_, false);
  const AxisTexels y = axisTexels(uv.y, height_, wrapV_, true);  // row 0 is the top (v = 1)
  const Rgb top = texel(x.i0, y.i0) * (1 - x.weight) + texel(x.i1, y.i0) * x.weight;
  const Rgb bottom = texel(x.i0, y.i1) * (1 - x.weight) + texel(x.i1, y.i1) * x.weight;
  return top * (1 - y.weight) + bottom * y.weight;
}

}  // namespace pathfarm
