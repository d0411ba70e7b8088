#pragma once
// An RGB image texture (PNG, JPEG, ... through stb_image), stored as linear floats.
// 8- and 16-bit images are taken as sRGB-encoded colour unless loaded as linear data
// (glTF's metallicRoughnessTexture); lookups are bilinear with repeat wrapping.
#include <filesystem>
#include <stdexcept>
#include <vector>

#include "renderer/math/vecmath.h"

namespace pathfarm {

class TextureError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// How integer texels map to values: colour through the sRGB curve, or data (metal,
// roughness) as plain fractions of the full scale. Float (HDR) images are linear either way.
enum class TextureEncoding { Srgb, Linear };

// What a lookup outside [0, 1] reads (glTF's sampler wrap modes).
enum class TextureWrap { Repeat, Clamp, Mirror };

class ImageTexture {
 public:
  static ImageTexture load(const std::filesystem::path& file, TextureEncoding encoding = TextureEncoding::Srgb);
  // From decoded pixels (rows top to bottom, `channels` interleaved 8- or 16-bit values,
  // little-endian for 16): grey and grey-alpha are replicated, alpha is dropped. `srgb`
  // says whether the values are sRGB-encoded colour or linear data.
  static ImageTexture fromPixels(int width, int height, int channels, int bitsPerChannel,
                                 const unsigned char* data, bool srgb);
  ImageTexture(int width, int height, std::vector<Rgb> texels);

  // Bilinear; outside [0, 1] as the wrap modes say (repeat unless set).
  Rgb lookup(Vec2f uv) const;
  void setWrap(TextureWrap u, TextureWrap v) {
    wrapU_ = u;
    wrapV_ = v;
  }
  // The mean of the texels, as repeat-wrapped bilinear lookups average over the unit square.
  Rgb average() const;
  int width() const { return width_; }
  int height() const { return height_; }

 private:
  Rgb texel(int x, int y) const;
  int width_, height_;
  std::vector<Rgb> texels_;  // row 0 is the top of the image (v = 1)
  TextureWrap wrapU_ = TextureWrap::Repeat, wrapV_ = TextureWrap::Repeat;
};

}  // namespace pathfarm
