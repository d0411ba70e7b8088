#!/usr/bin/python3
"""Directional albedo of glTF's dielectric as pathfarm and as Blender 3.4's Principled
BSDF model it: how much light a surface seen at cos(theta_o) returns under a uniform sky.
The numbers behind docs/performance.md's "Against Blender Cycles (issue 17)".

  albedo.py          (Debian's python3 with python3-numpy)

pathfarm (renderer/materials/metallic_roughness.h): GGX specular with the exact Fresnel of
ior 1.5, plus a base that reflects exactly rho (1 - E(cos_o)), E the specular albedo
(pathfarm uses a tabulated upper bound on E, about 1 % above; the exact E is used here).

Principled BSDF, Cycles 3.x: the same GGX specular (specular 0.5 means F0 = 0.08 * 0.5 =
0.04, i.e. ior 1.5; Fresnel mix(F0, 1, (F(ior) - F0) / (1 - F0)) is then F(ior) itself),
added to Disney's diffuse with its roughness-driven retro-reflection,
  rho / pi * [(1 - FV / 2) (1 - FL / 2) + RR (FL + FV + FL FV (RR - 1))],
  FL = (1 - cos_i)^5, FV = (1 - cos_o)^5, RR = roughness (1 + wi.wo),
whose weight is (1 - metallic) whatever the specular layer reflected.

Both use GGX with alpha = roughness^2 and the separable Smith shadowing G1(wo) G1(wi).
Integrals by midpoint quadrature over (cos_i, phi).
"""
import numpy as np

N_MU, N_PHI = 400, 400


def fresnel_dielectric(c, eta=1.5):
    c = np.clip(np.abs(c), 0, 1)
    g = np.sqrt(eta * eta - 1 + c * c)
    return 0.5 * ((g - c) / (g + c)) ** 2 * (1 + ((c * (g + c) - 1) / (c * (g - c) + 1)) ** 2)


def ggx_reflection(wo, wi, alpha, fresnel):
    """f * cos_i of the GGX reflection lobe, wo one direction, wi an array of them."""
    h = wo + wi
    h /= np.linalg.norm(h, axis=-1, keepdims=True)
    cos_h = h[..., 2]
    d = alpha ** 2 / (np.pi * (cos_h ** 2 * (alpha ** 2 - 1) + 1) ** 2)

    def g1(w):
        c = np.clip(w[..., 2], 1e-7, 1)
        return 2 / (1 + np.sqrt(1 + alpha ** 2 * (1 - c * c) / (c * c)))

    return fresnel(np.sum(wo * h, axis=-1)) * d * g1(wo) * g1(wi) / (4 * wo[2])


def disney_diffuse(wo, wi, roughness):
    """f * cos_i / rho."""
    fv, fl = (1 - wo[2]) ** 5, (1 - wi[..., 2]) ** 5
    rr = roughness * (1 + np.sum(wo * wi, axis=-1))
    return ((1 - fv / 2) * (1 - fl / 2) + rr * (fl + fv + fl * fv * (rr - 1))) / np.pi * wi[..., 2]


def hemisphere():
    """Midpoint directions and solid-angle weights over the upper hemisphere."""
    mu = (np.arange(N_MU) + 0.5) / N_MU
    phi = (np.arange(N_PHI) + 0.5) / N_PHI * 2 * np.pi
    m, p = np.meshgrid(mu, phi, indexing="ij")
    s = np.sqrt(1 - m * m)
    directions = np.stack([s * np.cos(p), s * np.sin(p), m], axis=-1).reshape(-1, 3)
    return directions, 2 * np.pi / (N_MU * N_PHI)


WI, DW = hemisphere()


def direction(cos_o):
    return np.array([np.sqrt(1 - cos_o ** 2), 0.0, cos_o])


def specular_albedo(cos_o, alpha):
    return float(np.sum(ggx_reflection(direction(cos_o), WI, alpha, fresnel_dielectric)) * DW)


def dielectric(rho, roughness, cos_o):
    alpha = roughness ** 2
    e = specular_albedo(cos_o, alpha)
    pathfarm = e + rho * (1 - e)
    cycles = e + rho * float(np.sum(disney_diffuse(direction(cos_o), WI, roughness)) * DW)
    return pathfarm, cycles


def metal_fresnel(f0, c):
    """Schlick (pathfarm, glTF's formula) against Principled's mix towards white."""
    schlick = f0 + (1 - f0) * (1 - c) ** 5
    principled = f0 + (1 - f0) * (fresnel_dielectric(c) - 0.04) / 0.96
    return schlick, principled


def main():
    angles = (1.0, 0.7, 0.4, 0.25)
    print("glTF dielectric (metallic 0), uniform sky: albedo pathfarm / Principled (ratio)\n")
    print("| material | rho | roughness | " + " | ".join(f"cos_o {c}" for c in angles) + " |")
    print("| --- | ---: | ---: | " + " | ".join("---:" for _ in angles) + " |")
    for name, rho, roughness in (("floor", 0.5, 0.8), ("matte", 0.8, 1.0), ("plastic (green)", 0.12, 0.5),
                                 ("plastic (red)", 0.7, 0.5), ("panel, cream", 0.67, 0.9),
                                 ("panel, blue", 0.06, 0.9)):
        cells = []
        for c in angles:
            pf, cy = dielectric(rho, roughness, c)
            cells.append(f"{pf:.3f} / {cy:.3f} ({pf / cy:.3f})")
        print(f"| {name} | {rho} | {roughness} | " + " | ".join(cells) + " |")
    print("\nGGX specular albedo E_s(cos_o) of the dielectric layer (ior 1.5)\n")
    for roughness in (0.5, 0.8, 1.0):
        print(f"roughness {roughness}: " + ", ".join(
            f"{c}: {specular_albedo(c, roughness ** 2):.3f}" for c in angles))
    print("\nglTF metal Fresnel at cos(wo.h): Schlick (pathfarm) / Principled\n")
    for f0 in (0.95, 0.34, 0.08):
        print(f"F0 {f0}: " + ", ".join(
            "{}: {:.3f} / {:.3f}".format(c, *metal_fresnel(f0, c)) for c in (1.0, 0.7, 0.4, 0.2, 0.1)))


if __name__ == "__main__":
    main()
