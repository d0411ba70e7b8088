#pragma once
// What the path tracers share at a surface vertex: the random numbers one bounce draws
// (the fixed per-bounce dimensions of the sampling contract, sample_stream.h) and the
// shading set up for a ray arriving at a hit.
#include "renderer/accel/surface_hit.h"
#include "renderer/materials/bsdf.h"
#include "renderer/math/frame.h"
#include "renderer/sampling/sample_stream.h"
#include "renderer/scene/scene.h"

namespace pathfarm {

// The uniform numbers one bounce consumes, drawn together so every bounce uses the same
// number of dimensions whatever happens in it.
struct BounceSamples {
  float light;
  Vec2f lightPoint;
  float lobe;
  Vec2f direction;
  float roulette;

  explicit BounceSamples(SampleStream& s)
      : light(s.next1D()), lightPoint(s.next2D()), lobe(s.next1D()), direction(s.next2D()), roulette(s.next1D()) {}
};

// The diffuse reflectance at a point (the filters' albedo feature): the texture replaces
// `reflectance`, except for glTF's base colour, which the texture multiplies.
inline Rgb albedoAt(const Scene& scene, const Material& material, Vec2f uv) {
  if (material.reflectanceTexture < 0) return material.reflectance;
  const Rgb texel = scene.textures[static_cast<size_t>(material.reflectanceTexture)].lookup(uv);
  return material.type == MaterialType::MetallicRoughness ? material.reflectance * texel : texel;
}

// Everything textured at a point. glTF's metallicRoughnessTexture holds linear data, metal
// in B and roughness in G, and the transmission texture in R, scaling the material's factors.
inline SurfaceParameters surfaceAt(const Scene& scene, const Material& material, Vec2f uv) {
  SurfaceParameters surface = SurfaceParameters::of(material, albedoAt(scene, material, uv));
  if (material.metallicRoughnessTexture >= 0) {
    const Rgb texel = scene.textures[static_cast<size_t>(material.metallicRoughnessTexture)].lookup(uv);
    surface.metallic *= texel.b;
    surface.roughness *= texel.g;
  }
  if (material.transmissionTexture >= 0)
    surface.transmission *= scene.textures[static_cast<size_t>(material.transmissionTexture)].lookup(uv).r;
  return surface;
}

inline bool isTransmissive(MaterialType type) {
  return type == MaterialType::Dielectric || type == MaterialType::RoughDielectric;
}

// A hit shaded for a ray arriving along `incoming`. Opaque surfaces are two-sided: the
// side the ray arrived on is shaded (normals flipped towards it), and so are the thin-walled
// metallic-roughness sheets, whose transmission has no inside. Dielectrics keep the outward
// normal so that the BSDF knows whether the ray is inside.
struct ShadedVertex {
  SurfaceHit hit;
  Vec3f normal;
  Frame frame;
  Vec3f wo;  // local
  Bsdf bsdf;

  ShadedVertex(const Scene& scene, const SurfaceHit& surface, Vec3f incoming)
      : hit(surface),
        normal(surface.shadingNormal),
        frame(),
        wo(),
        bsdf(materialOf(scene, surface), surfaceAt(scene, materialOf(scene, surface), surface.uv),
             scene.roughnessThreshold) {
    if (!isTransmissive(materialOf(scene, surface).type) && dot(incoming, hit.geometricNormal) > 0) {
      normal = -normal;
      hit.geometricNormal = -hit.geometricNormal;
    }
    frame = Frame::fromNormal(normal);
    wo = frame.toLocal(-incoming);
  }

  static const Material& materialOf(const Scene& scene, const SurfaceHit& surface) {
    return scene.materials[static_cast<size_t>(scene.objects[static_cast<size_t>(surface.object)].material)];
  }
};

}  // namespace pathfarm
