"""The Blender add-on, tested as an artist uses it (run by addon_test.sh inside Blender):
installed and enabled from the repository, a scene built in Python is submitted to a
local farm the add-on starts, and the frames that come back are checked: their number and
size, a cube that moves, the World's colour in the sky, and every light's brightness
against Cycles' render of the same scene, region by region. Bad input gets a message."""

import json
import os
import sys
import time
import zipfile

import bpy
import numpy

sys.path.insert(0, os.path.dirname(__file__))
import blender_scene  # noqa: E402

PATHFARM, REPOSITORY, WORK = sys.argv[sys.argv.index("--") + 1:]
SPP, MAX_DEPTH = 128, 3
REGIONS = (3, 3)  # columns x rows of the image, each compared on its own
TOLERANCE = 0.05  # at Principled's default roughness (blender_scene.py; docs/blender.md)
failures = []


def check(condition, message):
    print(("ok    " if condition else "FAIL  ") + message, flush=True)
    if not condition:
        failures.append(message)


def install_addon():
    archive = os.path.join(WORK, "pathfarm_blender.zip")
    source = os.path.join(REPOSITORY, "clients", "blender")
    with zipfile.ZipFile(archive, "w") as zipped:
        for folder, _, files in os.walk(os.path.join(source, "pathfarm_blender")):
            for name in files:
                if name.endswith(".py"):
                    path = os.path.join(folder, name)
                    zipped.write(path, os.path.relpath(path, source))
    bpy.ops.preferences.addon_install(filepath=archive, overwrite=True)
    bpy.ops.preferences.addon_enable(module="pathfarm_blender")
    import pathfarm_blender

    return pathfarm_blender


def pixels(path):
    """An EXR's RGB as a height x width x 3 array, top row first."""
    image = bpy.data.images.load(path, check_existing=False)
    width, height = image.size
    rgba = numpy.array(image.pixels[:], dtype=numpy.float64).reshape(height, width, 4)
    bpy.data.images.remove(image)
    return rgba[::-1, :, :3]


def region_means(rgb):
    columns, rows = REGIONS
    height, width, _ = rgb.shape
    return numpy.array([[rgb[r * height // rows:(r + 1) * height // rows,
                             c * width // columns:(c + 1) * width // columns].mean()
                         for c in range(columns)] for r in range(rows)])


def compare_regions(label, ours, cycles):
    a, b = region_means(ours), region_means(cycles)
    lit = b > 0.2 * b.max()  # where a light grazes the floor, the materials differ (docs/blender.md)
    deviations = a[lit] / b[lit] - 1
    worst = float(deviations[numpy.argmax(numpy.abs(deviations))])
    check(abs(worst) <= TOLERANCE, f"{label}: brightness within {TOLERANCE:.0%} of Cycles in every lit region "
                                   f"(worst {worst:+.1%}; pathfarm {numpy.round(a, 3).tolist()}, "
                              f"Cycles {numpy.round(b, 3).tolist()})")


def run_shot(addon, context):
    job = addon.operators.start_shot(context)
    deadline = time.monotonic() + 300
    while addon.operators.update_state(context) and time.monotonic() < deadline:
        time.sleep(0.2)
    check(job.state == "done", f"the shot ends done ({job.message})")
    return job


def test_round_trip(addon):
    scene = blender_scene.build(WORK)
    settings = scene.pathfarm
    settings.executable, settings.output = PATHFARM, os.path.join(WORK, "shot")
    settings.pipeline, settings.spp, settings.max_depth, settings.workers = "pt", SPP, MAX_DEPTH, 2
    settings.preview_every = 2  # frames 1 and 3 first: the shot file carries the key to the farm
    bpy.ops.wm.save_as_mainfile(filepath=os.path.join(WORK, "scene.blend"))
    job = run_shot(addon, bpy.context)
    warnings = [warning.text for warning in bpy.context.window_manager.pathfarm_job.warnings]
    check(any("panel: emits from both sides" in text for text in warnings),
          f"the panel's two-sided emission is listed as lost ({warnings})")
    with open(job.shot_file) as file:
        shot = json.load(file)
    check(shot.get("preview_every") == 2 and shot.get("pipeline") == "pt", f"the shot file carries the panel ({shot})")
    frames = job.frames()
    check(len(frames) == 3, f"three frames come back ({len(frames)})")
    if len(frames) != 3:
        return
    first, middle, last = (pixels(frame) for frame in frames)
    check(first.shape == (54, 96, 3), f"frames are 96x54 ({first.shape[1]}x{first.shape[0]})")
    loaded = [image for image in bpy.data.images if image.filepath == frames[0]]
    check(len(loaded) == 1 and loaded[0].source == "SEQUENCE", "the frames are loaded in Blender as an image sequence")
    # The cube is red: the reddest column moves right (it and the camera move along +x,
    # the cube twice as far).
    redness = [(frame[..., 0] - frame[..., 1]).sum(axis=0) for frame in (first, last)]
    columns = [int(numpy.argmax(numpy.convolve(r, numpy.ones(9), "same"))) for r in redness]
    check(columns[1] > columns[0] + 5, f"the cube moves right in the picture (column {columns[0]} to {columns[1]})")
    sky = middle[:4, :8].reshape(-1, 3).mean(axis=0)
    check(numpy.allclose(sky, blender_scene.SKY, rtol=0.02), f"the sky's corner is the World's colour ({sky.round(4)})")
    cycles = pixels(blender_scene.render_cycles(os.path.join(WORK, "cycles_all.exr"), 2, SPP, MAX_DEPTH - 1))
    compare_regions("every light and the World", middle, cycles)


def test_each_light(addon):
    """Each light alone (the World dark), one frame, against Cycles: the units of a point,
    a spot, a sun and an emissive mesh as Blender's exporter writes them."""
    scene = bpy.context.scene
    scene.frame_start = scene.frame_end = 2
    for light in blender_scene.LIGHTS:
        blender_scene.only_light(light)
        scene.pathfarm.output = os.path.join(WORK, "light_" + light)
        job = run_shot(addon, bpy.context)
        if job.frames():
            cycles = blender_scene.render_cycles(os.path.join(WORK, f"cycles_{light}.exr"), 2, SPP, MAX_DEPTH - 1)
            compare_regions(light, pixels(job.frames()[0]), pixels(cycles))


def test_environment_map(addon):
    """An HDR World lands the right way round: the sky and the floor it lights, region by
    region, against Cycles."""
    blender_scene.only_light(None)
    blender_scene.use_environment_map(WORK)
    bpy.context.scene.pathfarm.output = os.path.join(WORK, "environment")
    job = run_shot(addon, bpy.context)
    if job.frames():
        cycles = blender_scene.render_cycles(os.path.join(WORK, "cycles_environment.exr"), 2, SPP, MAX_DEPTH - 1)
        compare_regions("an HDR World", pixels(job.frames()[0]), pixels(cycles))


def test_bad_input(addon):
    """Clear messages, never a traceback: no camera, an unreachable farm, a wrong token."""
    from pathfarm_blender.farm_client import FarmError

    scene, settings = bpy.context.scene, bpy.context.scene.pathfarm
    camera, scene.camera = scene.camera, None
    try:
        addon.operators.start_shot(bpy.context)
        check(False, "a scene without a camera is refused")
    except FarmError as error:
        check("no active camera" in str(error), f"a scene without a camera is refused ({error})")
    scene.camera = camera
    settings.farm, settings.scheduler = "REMOTE", "127.0.0.1:1"
    settings.output = os.path.join(WORK, "unreachable")
    job = addon.operators.start_shot(bpy.context)
    deadline = time.monotonic() + 120
    while addon.operators.update_state(bpy.context) and time.monotonic() < deadline:
        time.sleep(0.2)
    check(job.state == "failed" and "submit failed" in job.message, f"an unreachable farm fails the submit ({job.message})")
    farm = addon.farm_client.local_farm(PATHFARM, os.path.join(WORK, "light_point", "farm"), 2)
    wrong_token = os.path.join(WORK, "wrong_token")
    with open(wrong_token, "w") as file:
        file.write("not the farm's token")
    settings.scheduler, settings.token_file = farm.address, wrong_token
    job = addon.operators.start_shot(bpy.context)
    while addon.operators.update_state(bpy.context) and time.monotonic() < deadline:
        time.sleep(0.2)
    check(job.state == "failed" and "token" in job.message.lower(), f"a wrong token is refused ({job.message})")
    settings.farm = "LOCAL"


def main():
    os.makedirs(WORK, exist_ok=True)
    addon = install_addon()
    try:
        test_round_trip(addon)
        test_each_light(addon)
        test_environment_map(addon)
        test_bad_input(addon)
    finally:
        addon.farm_client.stop_local_farm()
    print(f"{len(failures)} failed" if failures else "every check passed", flush=True)
    sys.exit(1 if failures else 0)


main()
