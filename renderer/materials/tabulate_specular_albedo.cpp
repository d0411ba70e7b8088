// Build step: writes specular_albedo.h's and multiple_scattering.h's tables as C++ source (the file named by the one
// argument), with hexadecimal float literals so that every node reads back exactly.
#include <cstdio>
#include <vector>

#include "renderer/materials/microfacet_albedo_tabulation.h"
#include "renderer/materials/specular_albedo_tabulation.h"

namespace {

void writeArray(std::FILE* out, const char* name, const std::vector<float>& values) {
  std::fprintf(out, "inline constexpr float %s[%zu] = {\n", name, values.size());
  for (size_t i = 0; i < values.size(); ++i)
    std::fprintf(out, "%af%s", double(values[i]), (i + 1) % 8 == 0 ? ",\n" : ", ");
  std::fprintf(out, "};\n");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s OUTPUT.inc\n", argv[0]);
    return 2;
  }
  using pathfarm::specular_albedo::Reflectance;
  const auto table = pathfarm::specular_albedo::tabulate(Reflectance::Fresnel);
  const auto excess = pathfarm::specular_albedo::tabulate(Reflectance::Excess);
  const auto microfacet = pathfarm::microfacet_albedo::tabulate();
  const auto dielectric = pathfarm::microfacet_albedo::tabulateDielectric();
  std::FILE* out = std::fopen(argv[1], "w");
  if (!out) {
    std::perror(argv[1]);
    return 1;
  }
  std::fprintf(out, "// Written by tabulate_specular_albedo at build time; do not edit.\n");
  writeArray(out, "kTabulatedAlbedo", table.albedo);
  writeArray(out, "kTabulatedAverage", table.average);
  writeArray(out, "kTabulatedExcessAlbedo", excess.albedo);
  writeArray(out, "kTabulatedExcessAverage", excess.average);
  writeArray(out, "kTabulatedMicrofacetAlbedo", microfacet.albedo);
  writeArray(out, "kTabulatedMicrofacetAverage", microfacet.average);
  writeArray(out, "kTabulatedDielectricAlbedo", dielectric.albedo);
  writeArray(out, "kTabulatedDielectricAverage", dielectric.average);
  return std::fclose(out) == 0 ? 0 : 1;
}
