#!/usr/bin/python3
"""Compares pathfarm's frame with Cycles' region by region (bench/cycles/compare.sh).

  compare.py PATHFARM.exr CYCLES_A.exr CYCLES_B.exr --layout layout.json
             [--grid 4] [--erode 2] [--png side_by_side.png] [--json out.json]
  compare.py stack OUT.png IN.png...      (the PNGs one above the other)

CYCLES_A and CYCLES_B are two Cycles renders of the same scene with different seeds;
their mean is the Cycles image and half their difference its noise. pathfarm's own
noise is its `variance.R/G/B` layer (the variance of each pixel's mean).

Regions: a grid of GRID x GRID cells of the frame, then one region per object (sky,
floor, panel, each sphere), found by casting each pixel centre's camera ray against the
analytic shapes of layout.json (make_scene.py's LAYOUT) and keeping the pixels whose
neighbours within ERODE pixels see the same object, so that silhouettes (where the
tessellated spheres and the analytic ones part, and where antialiasing mixes objects)
are left out.

Per region:
- ratio: mean of pathfarm's luminance over mean of Cycles' (and per channel);
- relMSE: mean over pixels and channels of (pf - cy)^2 / (cy^2 + 0.01), Cycles the
  reference (DESIGN.md's definition);
- noise: the relMSE that the two images' noise alone gives in expectation,
  mean of (var_pf + var_cy) / (cy^2 + 0.01); relMSE well above it is a real difference.

Reads EXR through OpenImageIO's Python module (Debian's python3-openimageio) and numpy.
"""
import argparse
import json
import math
import sys

import numpy as np
import OpenImageIO as oiio

LUMA = np.array([0.2126, 0.7152, 0.0722])


def read_exr(path, channels):
    image = oiio.ImageInput.open(path)
    if image is None:
        sys.exit(f"compare.py: cannot read {path}: {oiio.geterror()}")
    spec = image.spec()
    pixels = image.read_image(0, 0, 0, spec.nchannels, oiio.FLOAT)
    image.close()
    names = list(spec.channelnames)
    missing = [c for c in channels if c not in names]
    if missing:
        sys.exit(f"compare.py: {path} has no channel {missing[0]} (has {names})")
    return np.stack([pixels[:, :, names.index(c)] for c in channels], axis=-1).astype(np.float64)


def camera_rays(layout, width, height):
    camera = layout["camera"]
    eye, target = np.array(camera["eye"]), np.array(camera["target"])
    forward = (target - eye) / np.linalg.norm(target - eye)
    right = np.cross(forward, [0, 1, 0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    tan_half = math.tan(math.radians(camera["yfov_degrees"]) / 2)
    xs = (2 * (np.arange(width) + 0.5) / width - 1) * tan_half * width / height
    ys = (1 - 2 * (np.arange(height) + 0.5) / height) * tan_half
    px, py = np.meshgrid(xs, ys)
    directions = forward + px[..., None] * right + py[..., None] * up
    return eye, directions / np.linalg.norm(directions, axis=-1, keepdims=True)


def label_pixels(layout, width, height):
    """Names of the objects each pixel centre sees, and the label image (index into names)."""
    eye, d = camera_rays(layout, width, height)
    names = ["sky", "floor", "panel", "lamp"] + list(layout["spheres"])
    nearest = np.full((height, width), np.inf)
    label = np.zeros((height, width), dtype=int)

    def take(t, index):
        hit = (t > 1e-6) & (t < nearest)
        nearest[hit] = t[hit]
        label[hit] = index

    with np.errstate(divide="ignore", invalid="ignore"):
        # floor: y = 0, |x|, |z| <= half
        t = -eye[1] / d[..., 1]
        p = eye + t[..., None] * d
        half = layout["floor_half"]
        take(np.where((np.abs(p[..., 0]) <= half) & (np.abs(p[..., 2]) <= half), t, np.inf), 1)
        # panel: z = centre z, facing +z
        c, (hx, hy) = np.array(layout["panel"]["centre"]), layout["panel"]["half"]
        t = (c[2] - eye[2]) / d[..., 2]
        p = eye + t[..., None] * d
        take(np.where((np.abs(p[..., 0] - c[0]) <= hx) & (np.abs(p[..., 1] - c[1]) <= hy), t, np.inf), 2)
        # lamp: y = centre y
        c, (hx, hz) = np.array(layout["lamp"]["centre"]), layout["lamp"]["half"]
        t = (c[1] - eye[1]) / d[..., 1]
        p = eye + t[..., None] * d
        take(np.where((np.abs(p[..., 0] - c[0]) <= hx) & (np.abs(p[..., 2] - c[2]) <= hz), t, np.inf), 3)
        for index, centre in enumerate(layout["spheres"].values(), start=4):
            oc = eye - np.array(centre)
            b = np.sum(d * oc, axis=-1)
            disc = b * b - (oc @ oc - layout["radius"] ** 2)
            take(np.where(disc >= 0, -b - np.sqrt(np.maximum(disc, 0)), np.inf), index)
    return names, label


def erode(label, radius):
    """True where every pixel within radius (Chebyshev) has the same label."""
    keep = np.ones(label.shape, dtype=bool)
    height, width = label.shape
    padded = np.pad(label, radius, mode="edge")
    for dy in range(-radius, radius + 1):
        for dx in range(-radius, radius + 1):
            keep &= padded[radius + dy:radius + dy + height, radius + dx:radius + dx + width] == label
    return keep


def region_figures(pf, cy, noise, mask):
    n = int(mask.sum())
    if n == 0:
        return None
    a, b = pf[mask], cy[mask]
    denominator = b * b + 0.01
    mean_a, mean_b = a.mean(axis=0), b.mean(axis=0)
    return {"pixels": n,
            "pathfarm": float(mean_a @ LUMA), "cycles": float(mean_b @ LUMA),
            "ratio": float((mean_a @ LUMA) / (mean_b @ LUMA)),
            "ratio_rgb": [float(x) for x in mean_a / mean_b],
            "relmse": float(np.mean((a - b) ** 2 / denominator)),
            "noise": float(np.mean(noise[mask] / denominator))}


def srgb(linear):
    x = np.clip(linear, 0, 1)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)


def side_by_side(path, pf, cy, label_names, label, keep, grid, scale=2, limit=0.25):
    """pathfarm | Cycles | relative luminance difference (red: pathfarm brighter, blue:
    Cycles brighter, full at +-limit, 3x3 box-averaged against noise), object outlines
    in grey on the difference."""
    height, width = label.shape
    lp, lc = pf @ LUMA, cy @ LUMA
    kernel = np.ones((3, 3)) / 9
    padded_p, padded_c = np.pad(lp, 1, mode="edge"), np.pad(lc, 1, mode="edge")
    bp = sum(kernel[i, j] * padded_p[i:i + height, j:j + width] for i in range(3) for j in range(3))
    bc = sum(kernel[i, j] * padded_c[i:i + height, j:j + width] for i in range(3) for j in range(3))
    relative = np.clip((bp - bc) / (bc + 0.02) / limit, -1, 1)
    difference = np.zeros((height, width, 3))
    difference[..., 0] = np.maximum(relative, 0)
    difference[..., 2] = np.maximum(-relative, 0)
    difference[..., 1] = 0.25 * np.abs(relative)
    outline = ~erode(label, 1)
    difference[outline] = 0.35
    for k in range(1, grid):
        difference[k * height // grid, :] = np.maximum(difference[k * height // grid, :], 0.15)
        difference[:, k * width // grid] = np.maximum(difference[:, k * width // grid], 0.15)
    gap = np.ones((height, 2, 3))
    panels = np.concatenate([srgb(pf), gap, srgb(cy), gap, difference], axis=1)
    panels = np.repeat(np.repeat(panels, scale, axis=0), scale, axis=1)
    pixels = (panels * 255 + 0.5).astype(np.uint8)
    out = oiio.ImageOutput.create(path)
    out.open(path, oiio.ImageSpec(pixels.shape[1], pixels.shape[0], 3, oiio.UINT8))
    out.write_image(pixels)
    out.close()


def stack(out_path, paths):
    rows = []
    for path in paths:
        image = oiio.ImageInput.open(path)
        if image is None:
            sys.exit(f"compare.py: cannot read {path}: {oiio.geterror()}")
        rows.append(image.read_image(0, 0, 0, 3, oiio.UINT8))
        image.close()
    width = max(r.shape[1] for r in rows)
    gap = np.full((6, width, 3), 255, dtype=np.uint8)
    pieces = []
    for r in rows:
        pieces += [np.pad(r, ((0, 0), (0, width - r.shape[1]), (0, 0)), constant_values=255), gap]
    pixels = np.ascontiguousarray(np.concatenate(pieces[:-1], axis=0))
    out = oiio.ImageOutput.create(out_path)
    out.open(out_path, oiio.ImageSpec(width, pixels.shape[0], 3, oiio.UINT8))
    out.write_image(pixels)
    out.close()


def main():
    if len(sys.argv) > 2 and sys.argv[1] == "stack":
        stack(sys.argv[2], sys.argv[3:])
        return
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("pathfarm")
    parser.add_argument("cycles_a")
    parser.add_argument("cycles_b")
    parser.add_argument("--layout", required=True)
    parser.add_argument("--grid", type=int, default=4)
    parser.add_argument("--erode", type=int, default=2)
    parser.add_argument("--png")
    parser.add_argument("--json")
    args = parser.parse_args()

    pf = read_exr(args.pathfarm, ["R", "G", "B"])
    pf_var = read_exr(args.pathfarm, ["variance.R", "variance.G", "variance.B"])
    ca, cb = read_exr(args.cycles_a, ["R", "G", "B"]), read_exr(args.cycles_b, ["R", "G", "B"])
    if not (pf.shape == ca.shape == cb.shape):
        sys.exit(f"compare.py: sizes differ: {pf.shape[:2]}, {ca.shape[:2]}, {cb.shape[:2]}")
    cy = (ca + cb) / 2
    # Var of the mean of two independent estimates: E[(a - b)^2] / 4.
    cy_var = (ca - cb) ** 2 / 4
    noise = pf_var + cy_var
    height, width = pf.shape[:2]
    layout = json.load(open(args.layout))
    names, label = label_pixels(layout, width, height)
    keep = erode(label, args.erode)

    rows = [("frame", np.ones((height, width), dtype=bool))]
    for gy in range(args.grid):
        for gx in range(args.grid):
            mask = np.zeros((height, width), dtype=bool)
            mask[gy * height // args.grid:(gy + 1) * height // args.grid,
                 gx * width // args.grid:(gx + 1) * width // args.grid] = True
            rows.append((f"cell {gy},{gx}", mask))
    for index, name in enumerate(names):
        rows.append((name, keep & (label == index)))

    results = {}
    print("| region | pixels | pathfarm Y | Cycles Y | ratio Y | ratio R / G / B | relMSE | noise relMSE |")
    print("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
    for name, mask in rows:
        figures = region_figures(pf, cy, noise, mask)
        if figures is None:
            continue
        results[name] = figures
        rgb = " / ".join(f"{x:.3f}" for x in figures["ratio_rgb"])
        print(f"| {name} | {figures['pixels']} | {figures['pathfarm']:.4f} | {figures['cycles']:.4f} | "
              f"{figures['ratio']:.3f} | {rgb} | {figures['relmse']:.5f} | {figures['noise']:.5f} |")
    if args.json:
        json.dump(results, open(args.json, "w"), indent=2)
    if args.png:
        side_by_side(args.png, pf, cy, names, label, keep, args.grid)
        print(f"\nside by side (pathfarm | Cycles | difference): {args.png}")


if __name__ == "__main__":
    main()
