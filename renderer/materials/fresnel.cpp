#include "renderer/materials/fresnel.h"

namespace pathfarm {

DielectricFresnel fresnelDielectric(float cosThetaI, float eta) {
  const float cosI = std::clamp(cosThetaI, 0.0f, 1.0f);
  // Snell's law: sin_t = sin_i / eta.
  const float sin2T = (1 - cosI * cosI) / (eta * eta);
  if (sin2T >= 1) return {1, 0};
  const float cosT = std::sqrt(1 - sin2T);
  // Amplitude coefficients for s and p polarization, numerator and denominator divided by n_incident.
  const float rs = (cosI - eta * cosT) / (cosI + eta * cosT);
  const float rp = (eta * cosI - cosT) / (eta * cosI + cosT);
  return {0.5f * (rs * rs + rp * rp), cosT};
}

float fresnelConductor(float cosThetaI, float eta, float k) {
  // The Fresnel equations with a complex index, written with real arithmetic only:
  // a^2 + b^2 = |(eta + ik)^2 - sin^2|, then R_s and R_p as rational functions of a and cos.
  const float cos2 = std::clamp(cosThetaI * cosThetaI, 0.0f, 1.0f);
  const float sin2 = 1 - cos2;
  const float t0 = eta * eta - k * k - sin2;
  const float a2PlusB2 = std::sqrt(t0 * t0 + 4 * eta * eta * k * k);
  const float a = std::sqrt(std::max(0.0f, 0.5f * (a2PlusB2 + t0)));
  const float t1 = a2PlusB2 + cos2;
  const float t2 = 2 * std::sqrt(cos2) * a;
  const float rs = (t1 - t2) / (t1 + t2);
  const float t3 = cos2 * a2PlusB2 + sin2 * sin2;
  const float t4 = t2 * sin2;
  const float rp = rs * (t3 - t4) / (t3 + t4);
  return 0.5f * (rs + rp);
}

Rgb fresnelConductor(float cosThetaI, Rgb eta, Rgb k) {
  return {fresnelConductor(cosThetaI, eta.r, k.r), fresnelConductor(cosThetaI, eta.g, k.g),
          fresnelConductor(cosThetaI, eta.b, k.b)};
}

Rgb fresnelSchlick(float cosThetaI, Rgb f0) {
  const float m = 1 - std::clamp(cosThetaI, 0.0f, 1.0f);
  const float m2 = m * m;
  return f0 + (Rgb(1) - f0) * (m2 * m2 * m);
}

float fresnelDiffuseReflectance(float eta) {
  if (eta == 1) return 0;
  if (eta < 1) {
    // From the denser side: reciprocity of transmission and the n^2 change of etendue give
    // 1 - Fdr(eta) = eta^2 (1 - Fdr(1 / eta)), light past the critical angle being reflected.
    return 1 - eta * eta * (1 - fresnelDiffuseReflectance(1 / eta));
  }
  // The classical closed form of the hemispherical average of Fresnel reflectance for n > 1;
  // fresnel_test.cpp checks it against quadrature. Double: the terms cancel near n = 1.
  const double n = eta, n2 = n * n, n4 = n2 * n2;
  const double np1 = n + 1, n2p1 = n2 + 1, n4m1 = n4 - 1;
  const double fdr = 0.5 + (n - 1) * (3 * n + 1) / (6 * np1 * np1) +
                     n2 * (n2 - 1) * (n2 - 1) / (n2p1 * n2p1 * n2p1) * std::log((n - 1) / np1) -
                     2 * n2 * n * (n2 + 2 * n - 1) / (n2p1 * n4m1) +
                     8 * n4 * (n4 + 1) / (n2p1 * n4m1 * n4m1) * std::log(n);
  return static_cast<float>(fdr);
}

}  // namespace pathfarm
