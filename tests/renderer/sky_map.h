#pragma once
// Equirectangular sky maps for the tests, written as Radiance .hdr files (stb_image_write)
// rather than committed: a map is a function of the direction at each texel's centre.
//
// The orientation is docs/scene-format.md's, spelled out here independently of the
// renderer: texel (x, y) of a w x h map has its centre at u = (x + 1/2) / w across and
// v = (y + 1/2) / h down, polar angle theta = pi v from +y and azimuth phi = 2 pi (u - 1/2)
// from +x towards +z.
#include <stb_image_write.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>
#include <unistd.h>

#include <gtest/gtest.h>

#include "renderer/math/vecmath.h"

namespace pathfarm::test_support {

inline Vec3f skyMapDirection(double u, double v) {
  const double theta = M_PI * v, phi = 2 * M_PI * (u - 0.5);
  return {static_cast<float>(std::sin(theta) * std::cos(phi)), static_cast<float>(std::cos(theta)),
          static_cast<float>(std::sin(theta) * std::sin(phi))};
}

// Texels, the top row first, from radiance(direction at the texel's centre).
template <class Radiance>
std::vector<Rgb> skyMapTexels(int width, int height, const Radiance& radiance) {
  std::vector<Rgb> texels;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) texels.push_back(radiance(skyMapDirection((x + 0.5) / width, (y + 0.5) / height)));
  return texels;
}

// Writes the map to `file` through a temporary name and a rename, so that test processes
// running side by side never read half a file. RGBE keeps 8 bits of mantissa: values
// such as 0.5, 1, 2, 4 or 100 come back exactly.
inline void writeSkyMap(const std::filesystem::path& file, int width, int height, const std::vector<Rgb>& texels) {
  std::vector<float> data;
  for (const Rgb& t : texels) data.insert(data.end(), {t.r, t.g, t.b});
  std::filesystem::create_directories(file.parent_path());
  const std::filesystem::path temporary = file.string() + "." + std::to_string(getpid()) + ".tmp";
  ASSERT_NE(stbi_write_hdr(temporary.c_str(), width, height, 3, data.data()), 0) << temporary;
  std::filesystem::rename(temporary, file);
}

inline std::filesystem::path skyMapFolder() { return std::filesystem::temp_directory_path() / "pathfarm_sky_maps"; }

// A map of one radiance everywhere, `value` exactly representable (see writeSkyMap).
inline std::filesystem::path constantSkyMap(float value) {
  const std::filesystem::path file = skyMapFolder() / ("constant_" + std::to_string(value) + ".hdr");
  writeSkyMap(file, 16, 8, std::vector<Rgb>(16 * 8, Rgb(value)));
  return file;
}

// `above` on the upper hemisphere (y > 0), `below` on the lower one; an even height puts
// the horizon on a texel edge.
inline std::vector<Rgb> hemisphereSkyTexels(int width, int height, Rgb above, Rgb below) {
  return skyMapTexels(width, height, [&](Vec3f d) { return d.y > 0 ? above : below; });
}

}  // namespace pathfarm::test_support
