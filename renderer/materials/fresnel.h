#pragma once
// Fresnel reflectance of smooth interfaces, the building block of every specular and
// microfacet lobe. Cosines are measured on the incident side, in [0, 1].
#include "renderer/math/vecmath.h"

namespace pathfarm {

struct DielectricFresnel {
  float reflectance;  // 1 under total internal reflection
  float cosThetaT;    // cosine of the refracted direction (positive), 0 under total internal reflection
};

// Exact unpolarized reflectance of a dielectric interface; eta = n_transmitted / n_incident.
DielectricFresnel fresnelDielectric(float cosThetaI, float eta);

// Exact unpolarized reflectance of a conductor with complex IOR eta + i k, seen from a
// medium of index 1; the Rgb overload applies it per channel.
float fresnelConductor(float cosThetaI, float eta, float k);
Rgb fresnelConductor(float cosThetaI, Rgb eta, Rgb k);

// Schlick 1994: f0 + (1 - f0) (1 - cos)^5, with the normal-incidence reflectance f0.
Rgb fresnelSchlick(float cosThetaI, Rgb f0);

// Hemispherical (cosine-weighted) average of fresnelDielectric for light arriving
// uniformly from the incident side: Fdr = integral of F(cos, eta) 2 cos dcos.
float fresnelDiffuseReflectance(float eta);

// Snell refraction of wo (wo.m > 0) through the facet normal m, eta = n_transmitted /
// n_incident, given the refracted cosine fresnelDielectric returned.
inline Vec3f refract(Vec3f wo, Vec3f m, float eta, float cosThetaT) {
  return -wo / eta + m * (dot(wo, m) / eta - cosThetaT);
}

}  // namespace pathfarm
