#include "image/png_preview.h"

#include <stb_image_write.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace pathfarm {
namespace {

unsigned char encodeSrgb(float linear) {
  const float v = std::clamp(linear, 0.0f, 1.0f);
  const float encoded = v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
  return static_cast<unsigned char>(std::lround(encoded * 255.0f));
}

std::vector<unsigned char> srgbPixels(const FrameImage& frame, float exposure) {
  const std::vector<float>* planes[3] = {&frame.channel("R"), &frame.channel("G"),
                                         &frame.channel("B")};
  std::vector<unsigned char> pixels(frame.pixelCount() * 3);
  for (size_t i = 0; i < frame.pixelCount(); ++i) {
    for (int c = 0; c < 3; ++c) {
      const float v = (*planes[c])[i] * exposure;
      pixels[i * 3 + static_cast<size_t>(c)] = encodeSrgb(std::isfinite(v) ? v : 0.0f);
    }
  }
  return pixels;
}

void appendBytes(void* context, void* data, int size) {
  static_cast<std::string*>(context)->append(static_cast<const char*>(data), static_cast<size_t>(size));
}

}  // namespace

void writePngPreview(const std::filesystem::path& file, const FrameImage& frame, float exposure) {
  const std::vector<unsigned char> pixels = srgbPixels(frame, exposure);
  if (!stbi_write_png(file.c_str(), frame.width(), frame.height(), 3, pixels.data(),
                      frame.width() * 3))
    throw std::runtime_error(file.string() + ": cannot write the PNG preview");
}

std::string encodePngPreview(const FrameImage& frame, float exposure) {
  const std::vector<unsigned char> pixels = srgbPixels(frame, exposure);
  std::string png;
  if (!stbi_write_png_to_func(appendBytes, &png, frame.width(), frame.height(), 3, pixels.data(), frame.width() * 3))
    throw std::runtime_error("cannot encode the PNG preview");
  return png;
}

}  // namespace pathfarm
