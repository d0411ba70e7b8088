#include "renderer/setup/auto_decomposition.h"

#include <spdlog/spdlog.h>

#include "renderer/integrators/frame_renderer.h"
#include "renderer/materials/bsdf.h"

namespace pathfarm {
namespace {

// Whether any material that a shape uses has a lobe counting as `symbol`.
bool sceneHasLobe(const Scene& scene, LobeSymbol symbol) {
  for (const SceneObject& object : scene.objects) {
    const Material& material = scene.materials[static_cast<size_t>(object.material)];
    const LobeList lobes = Bsdf(material, material.reflectance, scene.roughnessThreshold).lobes();
    for (int l = 0; l < lobes.count; ++l)
      if (lobes.lobes[l].symbol == symbol) return true;
  }
  return false;
}

double luminanceSum(const FrameImage& image, const std::string& layer) {
  const auto& r = image.channel(layer + "R");
  const auto& g = image.channel(layer + "G");
  const auto& b = image.channel(layer + "B");
  double sum = 0;
  for (size_t p = 0; p < r.size(); ++p) sum += Rgb(r[p], g[p], b[p]).luminance();
  return sum;
}

}  // namespace

Decomposition chooseDecomposition(const Scene& scene, const AutoDecompositionSettings& settings) {
  std::vector<Component> components{{"diffuse_direct", "ED"}, {"diffuse_indirect", "ED.+"}};
  if (sceneHasLobe(scene, LobeSymbol::R)) components.push_back({"reflection", "ERD.*"});
  if (sceneHasLobe(scene, LobeSymbol::T)) {
    components.push_back({"transmission", "ETTD.*"});
    // Probe: is light seen through two glass shells worth a component of its own?
    std::vector<Component> probe = components;
    probe.push_back({"transmission_deep", "ETTTTD.*"});
    RenderSettings render;
    render.width = settings.probeWidth;
    render.height = settings.probeHeight;
    render.spp = settings.probeSpp;
    render.maxDepth = scene.defaults.maxDepth;
    render.decomposition = std::make_shared<Decomposition>(probe);
    const FrameImage image = FrameRenderer(scene, render).render(settings.probeFrame);
    const double total = luminanceSum(image, "");
    const double deep = luminanceSum(image, "transmission_deep.color.");
    const double share = total > 0 ? deep / total : 0;
    spdlog::debug("auto decomposition probe: ETTTTD.* carries {:.2f} % of the energy", 100 * share);
    if (share > settings.deepShareThreshold) components.push_back(probe.back());
  }
  Decomposition chosen(components);
  spdlog::info("decomposition (auto): {}", chosen.describe());
  return chosen;
}

std::shared_ptr<const Decomposition> decompositionFor(const Scene& scene, const std::string& spec) {
  if (spec == "none") return nullptr;
  if (spec == "auto") return std::make_shared<Decomposition>(chooseDecomposition(scene));
  return std::make_shared<Decomposition>(Decomposition::parse(spec));
}

}  // namespace pathfarm
