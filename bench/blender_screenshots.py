"""Screenshots of the add-on for docs/blender.md, taken in a real Blender window (run by
bench/blender_screenshots.sh under Xvfb): the panel after a shot, with its frames loaded
in the Image Editor."""

import os
import sys
import time

import bpy

PATHFARM, REPOSITORY, OUT = sys.argv[sys.argv.index("--") + 1:]
sys.path.insert(0, os.path.join(REPOSITORY, "tests", "blender"))
sys.path.insert(0, os.path.join(REPOSITORY, "clients", "blender"))
import blender_scene  # noqa: E402
import pathfarm_blender  # noqa: E402


def areas_of(kind):
    return [area for area in bpy.context.window.screen.areas if area.type == kind]


def set_up():
    pathfarm_blender.register()
    scene = blender_scene.build(OUT, resolution=(320, 180), frames=(1, 12))
    settings = scene.pathfarm
    settings.executable, settings.output, settings.spp, settings.max_depth = PATHFARM, os.path.join(OUT, "shot"), 16, 4
    scene.render.engine = "CYCLES"
    for area in areas_of("PROPERTIES"):
        area.spaces.active.context = "RENDER"
    # The 3D viewport becomes the Image Editor the frames load into.
    viewport = max(areas_of("VIEW_3D"), key=lambda area: area.width * area.height)
    viewport.type = "IMAGE_EDITOR"
    bpy.ops.pathfarm.submit()
    bpy.app.timers.register(follow, first_interval=0.5)


def follow():
    if pathfarm_blender.operators.update_state(bpy.context):
        return 0.5
    bpy.context.scene.frame_set(6)
    bpy.app.timers.register(shoot, first_interval=1.0)
    return None


def shoot():
    # The add-on's panel comes after the engine's: scroll the Render properties to it.
    for area in areas_of("PROPERTIES"):
        region = next(region for region in area.regions if region.type == "WINDOW")
        with bpy.context.temp_override(area=area, region=region):
            for _ in range(40):
                bpy.ops.view2d.scroll_down(page=True)
    for area in areas_of("IMAGE_EDITOR"):
        region = next(region for region in area.regions if region.type == "WINDOW")
        with bpy.context.temp_override(area=area, region=region):
            bpy.ops.image.view_all(fit_view=True)
    bpy.app.timers.register(save, first_interval=0.5)
    return None


def save():
    bpy.ops.screen.screenshot(filepath=os.path.join(OUT, "blender_panel.png"))
    pathfarm_blender.farm_client.stop_local_farm()
    bpy.ops.wm.quit_blender()


bpy.app.timers.register(set_up, first_interval=1.0)
