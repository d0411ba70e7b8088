#!/usr/bin/env python3
"""Writes the comparison scene for the Blender Cycles check (bench/cycles/compare.sh).

A static glTF 2.0 scene, compare.glb, that both renderers import: a rough grey floor, a
textured panel behind, four spheres (red rough plastic, white matte dielectric, rough gold,
near-mirror chrome) under an emissive panel (emissiveFactor x KHR_materials_emissive_strength)
and a constant sky, seen by one perspective camera. Every material is plain
pbrMetallicRoughness, so the two importers have nothing to interpret differently.

Two variants: "authored" (the materials above) and "metal" (the same scene with
metallicFactor 1 on every surface but the lamp). glTF's metal is one GGX lobe with a
Fresnel towards the base colour in both renderers, while its dielectric (a specular layer
over a diffuse base) is where pathfarm's model and Blender's Principled BSDF part, so the
metal variant checks the light transport (camera, sky, emitter, textures, interreflection)
with the material difference reduced to the Fresnel curve.

Beside it, scene.json: the pathfarm scene that includes compare.glb and adds the constant
sky, the seed and the path depth (glTF has no sky). Cycles gets the same sky and depth
from render_cycles.py's options.

The geometry is also exported as LAYOUT (and written to layout.json) so that compare.py
can label every pixel with the object it sees by casting rays against the same analytic
shapes.

Standard library only; the glTF writer, PNG encoder and mesh helpers are the showroom's
(scenes/showroom/make_scene.py), imported from there.

  make_scene.py --out DIR [--variant authored|metal] [--sky R,G,B] [--max-depth N] [--seed N]
"""
import argparse
import importlib.util
import json
import math
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def _showroom():
    sys.dont_write_bytecode = True  # leave no __pycache__ in scenes/showroom
    spec = importlib.util.spec_from_file_location("showroom_make_scene", ROOT / "scenes/showroom/make_scene.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


SR = _showroom()

CAMERA = {"eye": [0.0, 1.25, 4.6], "target": [0.0, 0.5, 0.0], "yfov_degrees": 38.0, "aspect": 4 / 3}
RADIUS = 0.45
# name -> (centre, pbrMetallicRoughness); metallic 0 means glTF's dielectric (F0 = 0.04
# specular over a diffuse base), metallic 1 a conductor with F0 = base colour.
SPHERES = {
    "plastic": ([-1.65, RADIUS, 0.0], {"baseColorFactor": [0.70, 0.12, 0.08, 1], "metallicFactor": 0,
                                       "roughnessFactor": 0.5}),
    "matte": ([-0.55, RADIUS, 0.0], {"baseColorFactor": [0.80, 0.80, 0.80, 1], "metallicFactor": 0,
                                     "roughnessFactor": 1.0}),
    "rough_gold": ([0.55, RADIUS, 0.0], {"baseColorFactor": [1.0, 0.78, 0.34, 1], "metallicFactor": 1,
                                         "roughnessFactor": 0.45}),
    "chrome": ([1.65, RADIUS, 0.0], {"baseColorFactor": [0.95, 0.95, 0.95, 1], "metallicFactor": 1,
                                     "roughnessFactor": 0.05}),
}
FLOOR = {"half": 6.0, "pbr": {"baseColorFactor": [0.5, 0.5, 0.5, 1], "metallicFactor": 0, "roughnessFactor": 0.8}}
# A vertical textured panel facing +z (bottom edge on the floor).
PANEL = {"centre": [0.0, 0.75, -1.6], "half": [2.2, 0.75],
         "pbr": {"baseColorTexture": {"index": 0}, "metallicFactor": 0, "roughnessFactor": 0.9}}
# The key light: a rectangle facing straight down, out of the camera's view.
LAMP = {"centre": [0.4, 3.0, 1.2], "half": [0.6, 0.4], "emissive": [1.0, 0.93, 0.82], "strength": 40.0}

LAYOUT = {"camera": CAMERA, "radius": RADIUS, "spheres": {k: v[0] for k, v in SPHERES.items()},
          "floor_half": FLOOR["half"], "panel": {"centre": PANEL["centre"], "half": PANEL["half"]},
          "lamp": {"centre": LAMP["centre"], "half": LAMP["half"]}}


def panel_texture(x, y, width=256, height=96, cells=(8, 3)):
    """A two-tone checker with a red marker in the top-left cell, so a flipped or mirrored
    uv mapping shows at once."""
    cw, ch = width // cells[0], height // cells[1]
    if x < cw and y < ch and cw // 4 < x < 3 * cw // 4 and ch // 4 < y < 3 * ch // 4:
        return (200, 30, 20)
    return (215, 205, 180) if ((x // cw) + (y // ch)) % 2 == 0 else (40, 70, 120)


def write(out, sky, max_depth, seed, variant="authored"):
    def pbr(fields):
        return dict(fields, metallicFactor=1) if variant == "metal" else fields

    w = SR.Writer()
    w.gltf["asset"]["generator"] = "pathfarm bench/cycles/make_scene.py"
    image = w.view(SR.png(256, 96, panel_texture))
    w.gltf["images"].append({"bufferView": image, "mimeType": "image/png"})
    w.gltf["samplers"].append({"magFilter": 9729, "minFilter": 9729, "wrapS": 33071, "wrapT": 33071})
    w.gltf["textures"].append({"source": 0, "sampler": 0})
    w.gltf["extensionsUsed"] = ["KHR_materials_emissive_strength"]

    nodes = [w.node(name="floor", mesh=w.mesh("floor", *SR.quad(FLOOR["half"], FLOOR["half"]),
                                               w.material("floor", pbrMetallicRoughness=pbr(FLOOR["pbr"]))))]
    hx, hy = PANEL["half"]
    nodes.append(w.node(name="panel", mesh=w.mesh("panel", *SR.quad(hx, hy), w.material(
        "panel", pbrMetallicRoughness=pbr(PANEL["pbr"]))), translation=PANEL["centre"],
        rotation=SR.axis_angle((1, 0, 0), 90)))
    # A finer tessellation than the showroom's, so the faceting of the smooth-shaded
    # spheres matters less where the analytic labels meet the meshes.
    # One set of vertex data; each sphere's mesh points at it with its own material.
    ball = None
    for name, (centre, fields) in SPHERES.items():
        material = w.material(name, pbrMetallicRoughness=pbr(fields))
        if ball is None:
            mesh = ball = w.mesh(name, *SR.sphere(48, 96), material)
        else:
            primitive = dict(w.gltf["meshes"][ball]["primitives"][0], material=material)
            w.gltf["meshes"].append({"name": name, "primitives": [primitive]})
            mesh = len(w.gltf["meshes"]) - 1
        nodes.append(w.node(name=name, mesh=mesh, translation=centre, scale=[RADIUS] * 3))
    lamp = w.material("lamp", emissiveFactor=LAMP["emissive"],
                      pbrMetallicRoughness={"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0, "roughnessFactor": 1},
                      extensions={"KHR_materials_emissive_strength": {"emissiveStrength": LAMP["strength"]}})
    nodes.append(w.node(name="lamp", mesh=w.mesh("lamp", *SR.quad(*LAMP["half"]), lamp),
                        translation=LAMP["centre"], rotation=SR.axis_angle((1, 0, 0), 180)))
    w.gltf["cameras"].append({"name": "view", "type": "perspective", "perspective": {
        "yfov": math.radians(CAMERA["yfov_degrees"]), "aspectRatio": CAMERA["aspect"], "znear": 0.05}})
    nodes.append(w.node(name="camera", camera=0, translation=CAMERA["eye"],
                        rotation=SR.look_rotation(CAMERA["eye"], CAMERA["target"])))
    w.gltf["scenes"] = [{"name": "cycles_compare", "nodes": nodes}]
    w.gltf["scene"] = 0

    out.mkdir(parents=True, exist_ok=True)
    (out / "compare.glb").write_bytes(w.glb())
    scene = {"include": "compare.glb", "seed": seed,
             "render": {"resolution": [256, 192], "spp": 1024, "max_depth": max_depth, "frames": [0, 0]},
             "environment": {"radiance": sky}}
    (out / "scene.json").write_text(json.dumps(scene, indent=2) + "\n")
    (out / "layout.json").write_text(json.dumps(LAYOUT, indent=2) + "\n")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, required=True)
    parser.add_argument("--variant", choices=("authored", "metal"), default="authored")
    parser.add_argument("--sky", default="0.25,0.3,0.4", help="constant sky radiance R,G,B")
    parser.add_argument("--max-depth", type=int, default=8)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    sky = [float(c) for c in args.sky.split(",")]
    if len(sky) != 3:
        parser.error("--sky needs three numbers")
    write(args.out, sky, args.max_depth, args.seed, args.variant)
    print(f"wrote {args.out / 'compare.glb'}, {args.out / 'scene.json'}")


if __name__ == "__main__":
    main()
