"""Renders a glTF 2.0 file with Blender Cycles, set up to be compared with pathfarm.

  blender -b --python-exit-code 1 -P render_cycles.py -- IN.glb OUT.exr W H SPP
          [--sky R,G,B] [--max-depth N] [--seed N] [--threads N] [--distribution asis|GGX|MULTI_GGX]

Written for Debian 12's Blender 3.4 and its glTF add-on; what it works around:
- The add-on's mesh import uses numpy.bool, which numpy 1.24 removed: the alias is put
  back before the import runs.
- glTF's yfov must land on the vertical sensor axis whatever the image's aspect ratio
  (a known trap of this importer: yfov applied to the horizontal axis for wide images).
  On the comparison scene the 3.4.1 add-on's camera came out right (sensor_fit VERTICAL,
  angle_y = yfov); the script sets both again from the file's own JSON regardless, so
  the view does not depend on the add-on's version.
- The add-on assigns only one of several glTF animations; the comparison scene is static, so
  nothing here depends on that (a scene with several animations must merge them).

Render settings chosen to match pathfarm's `render` on the same scene: Cycles on the CPU,
no denoiser, no adaptive sampling, no clamping, no glossy filter, caustics on, a one-pixel
box pixel filter, a fixed seed, max bounces = pathfarm's max depth - 1 (pathfarm counts
scattering events with direct light as 1, Cycles counts bounces after the first hit), a
constant world colour as the sky, the Standard view transform with no exposure and a
32-bit float ZIP OpenEXR of the linear render (no compositor).
"""
import json
import struct
import sys
import time

import numpy

# numpy 1.24 removed the deprecated alias the add-on's importer still uses.
if "bool" not in vars(numpy):
    numpy.bool = bool

import bpy  # noqa: E402  (after the numpy alias, before the add-on runs)


def fail(message):
    print(f"render_cycles: {message}", file=sys.stderr)
    sys.exit(2)


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    positional, options = [], {"sky": "0,0,0", "max-depth": "8", "seed": "0", "threads": "2",
                               "distribution": "asis"}
    i = 0
    while i < len(argv):
        if argv[i].startswith("--"):
            key = argv[i][2:]
            if key not in options or i + 1 >= len(argv):
                fail(f"unknown option or missing value: {argv[i]}")
            options[key] = argv[i + 1]
            i += 2
        else:
            positional.append(argv[i])
            i += 1
    if len(positional) != 5:
        fail("usage: blender -b --python-exit-code 1 -P render_cycles.py -- IN.glb OUT.exr W H SPP [options]")
    gltf, out, width, height, spp = positional
    sky = [float(c) for c in options["sky"].split(",")]
    if len(sky) != 3:
        fail("--sky needs R,G,B")
    if options["distribution"] not in ("asis", "GGX", "MULTI_GGX"):
        fail("--distribution is asis, GGX or MULTI_GGX")
    return (gltf, out, int(width), int(height), int(spp), sky, int(options["max-depth"]), int(options["seed"]),
            int(options["threads"]), options["distribution"])


def gltf_json(path):
    """The JSON of a .glb (first chunk) or .gltf file."""
    data = open(path, "rb").read()
    if data[:4] == b"glTF":
        length, kind = struct.unpack_from("<I4s", data, 12)
        if kind != b"JSON":
            fail(f"{path}: first GLB chunk is not JSON")
        return json.loads(data[20:20 + length])
    return json.loads(data)


def main():
    gltf, out, width, height, spp, sky, max_depth, seed, threads, distribution = parse_args()
    document = gltf_json(gltf)

    bpy.ops.wm.read_factory_settings(use_empty=True)
    result = bpy.ops.import_scene.gltf(filepath=gltf)
    if "FINISHED" not in result:
        fail(f"glTF import of {gltf} failed: {result}")
    scene = bpy.context.scene

    # The camera: the first glTF camera node, with the yfov put on the vertical axis.
    cameras = [o for o in scene.objects if o.type == "CAMERA"]
    if not cameras:
        fail(f"{gltf}: no camera imported")
    camera = cameras[0]
    yfov = None
    for node in document.get("nodes", []):
        if "camera" in node:
            yfov = document["cameras"][node["camera"]]["perspective"]["yfov"]
            break
    camera.data.sensor_fit = "VERTICAL"
    camera.data.lens_unit = "FOV"
    camera.data.angle_y = yfov
    camera.data.shift_x = camera.data.shift_y = 0
    scene.camera = camera

    # Materials: report what the importer made of them (and optionally pin the microfacet
    # distribution of every Principled BSDF).
    for material in bpy.data.materials:
        if not material.use_nodes:
            continue
        for node in material.node_tree.nodes:
            if node.type == "BSDF_PRINCIPLED":
                if distribution != "asis":
                    node.distribution = distribution
                values = {name: node.inputs[name].default_value for name in
                          ("Metallic", "Roughness", "Specular", "Specular Tint", "IOR", "Emission Strength")}
                print(f"render_cycles: material {material.name}: Principled {node.distribution} "
                      + ", ".join(f"{k} {v:.3g}" for k, v in values.items()))

    world = bpy.data.worlds.new("sky")
    world.use_nodes = True
    background = world.node_tree.nodes["Background"]
    background.inputs["Color"].default_value = (*sky, 1.0)
    background.inputs["Strength"].default_value = 1.0
    scene.world = world

    render = scene.render
    render.engine = "CYCLES"
    render.resolution_x, render.resolution_y, render.resolution_percentage = width, height, 100
    render.pixel_aspect_x = render.pixel_aspect_y = 1
    render.threads_mode = "FIXED"
    render.threads = threads
    render.use_compositing = False
    render.use_sequencer = False
    render.film_transparent = False
    render.use_motion_blur = False
    render.image_settings.file_format = "OPEN_EXR"
    render.image_settings.color_depth = "32"
    render.image_settings.exr_codec = "ZIP"
    render.filepath = out
    render.use_file_extension = False

    view = scene.view_settings
    view.view_transform = "Standard"
    view.look = "None"
    view.exposure = 0
    view.gamma = 1

    cycles = scene.cycles
    cycles.device = "CPU"
    cycles.samples = spp
    cycles.use_adaptive_sampling = False
    cycles.use_denoising = False
    cycles.seed = seed
    cycles.use_animated_seed = False
    bounces = max(max_depth - 1, 0)
    cycles.max_bounces = bounces
    cycles.diffuse_bounces = cycles.glossy_bounces = cycles.transmission_bounces = bounces
    cycles.volume_bounces = cycles.transparent_max_bounces = bounces
    cycles.sample_clamp_direct = 0
    cycles.sample_clamp_indirect = 0
    cycles.blur_glossy = 0
    cycles.caustics_reflective = cycles.caustics_refractive = True
    cycles.light_sampling_threshold = 0
    cycles.filter_type = "BOX"
    cycles.filter_width = 1.0
    cycles.film_exposure = 1.0

    print(f"render_cycles: {width}x{height}, {spp} spp, {bounces} bounces, sky {sky}, "
          f"camera {camera.name} angle_y {camera.data.angle_y:.4f} rad, {threads} threads")
    start = time.time()
    bpy.ops.render.render(write_still=True)
    print(f"render_cycles: wrote {out} in {time.time() - start:.1f} s")


main()
