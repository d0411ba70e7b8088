"""The test scene, built in Blender's Python: a dolly camera, a cube that moves, a
textured floor, a point light, a spot, a sun, an emissive panel and a coloured World,
every surface diffuse: Principled with Specular 0 at Blender's default roughness, 0.5, where
Cycles' Burley diffuse lobe stays nearest Lambert's (docs/blender.md)."""

import math
import os

import bpy

SKY = (0.2, 0.3, 0.5)
LIGHTS = ("point", "spot", "sun", "panel")


def diffuse_material(name, color, image=None):
    material = bpy.data.materials.new(name)
    material.use_nodes = True
    principled = material.node_tree.nodes["Principled BSDF"]
    principled.inputs["Base Color"].default_value = (*color, 1)
    principled.inputs["Roughness"].default_value = 0.5
    principled.inputs["Specular"].default_value = 0.0
    if image is not None:
        texture = material.node_tree.nodes.new("ShaderNodeTexImage")
        texture.image = image
        material.node_tree.links.new(texture.outputs["Color"], principled.inputs["Base Color"])
    return material


def emissive_material(name, strength):
    material = bpy.data.materials.new(name)
    material.use_nodes = True
    principled = material.node_tree.nodes["Principled BSDF"]
    principled.inputs["Base Color"].default_value = (0, 0, 0, 1)
    principled.inputs["Specular"].default_value = 0.0
    principled.inputs["Emission"].default_value = (1, 1, 1, 1)
    principled.inputs["Emission Strength"].default_value = strength
    return material


def checker_image(folder, size=64, squares=8):
    """A grey checker (0.3 and 0.7 in linear light), saved as a PNG the glTF file embeds."""
    image = bpy.data.images.new("checker", size, size)
    pixels = []
    for y in range(size):
        for x in range(size):
            value = 0.7 if ((x * squares // size) + (y * squares // size)) % 2 else 0.3
            srgb = 1.055 * value ** (1 / 2.4) - 0.055
            pixels += [srgb, srgb, srgb, 1]
    image.pixels = pixels
    image.filepath_raw = os.path.join(folder, "checker.png")
    image.file_format = "PNG"
    image.save()
    return image


def keyframes(obj, path, values):
    for frame, value in values.items():
        setattr(obj, path, value)
        obj.keyframe_insert(path, frame=frame)
    for curve in obj.animation_data.action.fcurves:
        for key in curve.keyframe_points:
            key.interpolation = "LINEAR"


def build(folder, resolution=(96, 54), frames=(1, 3)):
    """Replaces the factory scene's content; returns the scene."""
    scene = bpy.context.scene
    for obj in list(scene.objects):
        bpy.data.objects.remove(obj)
    scene.render.resolution_x, scene.render.resolution_y = resolution
    scene.render.resolution_percentage = 100
    scene.frame_start, scene.frame_end = frames
    scene.render.fps, scene.render.fps_base = 24, 1
    scene.render.use_motion_blur = False

    bpy.ops.mesh.primitive_plane_add(size=8, location=(0, 0, 0))
    floor = bpy.context.object
    floor.name = "floor"
    floor.data.materials.append(diffuse_material("floor", (1, 1, 1), checker_image(folder)))

    bpy.ops.mesh.primitive_cube_add(size=1, location=(-1, 0, 0.5))
    cube = bpy.context.object
    cube.name = "cube"
    cube.data.materials.append(diffuse_material("cube", (0.8, 0.2, 0.1)))
    keyframes(cube, "location", {frames[0]: (-1, 0, 0.5), frames[1]: (1, 0, 0.5)})

    # Facing down from above the camera, which never sees its back: Cycles emits from both
    # sides of a mesh, pathfarm from the front face.
    bpy.ops.mesh.primitive_plane_add(size=1.5, location=(1.5, 1, 5.5), rotation=(math.pi, 0, 0))
    panel = bpy.context.object
    panel.name = "panel"
    panel.data.materials.append(emissive_material("panel", 4.0))

    add_light("point", "POINT", (-2, -2, 2.5), (0, 0, 0), energy=200)
    spot = add_light("spot", "SPOT", (2, -2, 3), (math.radians(35), 0, math.radians(45)), energy=400)
    spot.data.spot_size, spot.data.spot_blend = math.radians(50), 0.05
    add_light("sun", "SUN", (0, 0, 5), (math.radians(40), math.radians(20), 0), energy=1.5)

    camera_data = bpy.data.cameras.new("camera")
    camera = bpy.data.objects.new("camera", camera_data)
    scene.collection.objects.link(camera)
    camera.rotation_euler = (math.radians(56), 0, 0)
    keyframes(camera, "location", {frames[0]: (-0.5, -6, 5), frames[1]: (0.5, -5.8, 5)})
    scene.camera = camera

    world = bpy.data.worlds.new("sky")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (*SKY, 1)
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 1.0
    scene.world = world
    return scene


def use_environment_map(folder, width=64, height=32):
    """The World as an equirectangular HDR image: four azimuth quarters of different
    brightness and a darker lower half, so a map turned or flipped shows."""
    image = bpy.data.images.new("sky_map", width, height, float_buffer=True)
    quarters = ((1.5, 0.6, 0.3), (0.2, 0.4, 1.2), (0.8, 0.8, 0.8), (0.1, 0.9, 0.2))
    pixels = []
    for y in range(height):  # Blender's rows run bottom to top
        for x in range(width):
            scale = 1.0 if y >= height // 2 else 0.3
            pixels += [c * scale for c in quarters[x * 4 // width]] + [1]
    image.pixels = pixels
    image.filepath_raw = os.path.join(folder, "sky_map.hdr")
    image.file_format = "HDR"
    image.save()
    world = bpy.context.scene.world
    texture = world.node_tree.nodes.new("ShaderNodeTexEnvironment")
    texture.image = bpy.data.images.load(image.filepath_raw)
    world.node_tree.links.new(texture.outputs["Color"], world.node_tree.nodes["Background"].inputs["Color"])


def add_light(name, kind, location, rotation, energy):
    data = bpy.data.lights.new(name, kind)
    data.energy = energy
    if kind == "SUN":
        data.angle = 0
    else:
        data.shadow_soft_size = 0
    obj = bpy.data.objects.new(name, data)
    obj.location, obj.rotation_euler = location, rotation
    bpy.context.scene.collection.objects.link(obj)
    return obj


def only_light(name):
    """Turns every light off but `name` (the World too): each is compared on its own."""
    for light in ("point", "spot", "sun"):
        bpy.data.objects[light].data.energy = {"point": 200, "spot": 400, "sun": 1.5}[light] if light == name else 0
    emission = bpy.data.materials["panel"].node_tree.nodes["Principled BSDF"].inputs["Emission Strength"]
    emission.default_value = 4.0 if name == "panel" else 0
    background = bpy.context.scene.world.node_tree.nodes["Background"].inputs["Strength"]
    background.default_value = 1.0 if name is None else 0


def render_cycles(path, frame, samples, bounces):
    """Cycles at the same bounces, without denoising, clamping or adaptive sampling."""
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    cycles = scene.cycles
    cycles.samples, cycles.use_denoising, cycles.use_adaptive_sampling = samples, False, False
    cycles.max_bounces = cycles.diffuse_bounces = cycles.glossy_bounces = bounces
    cycles.transmission_bounces = cycles.transparent_max_bounces = bounces
    cycles.sample_clamp_direct = cycles.sample_clamp_indirect = 0
    cycles.seed = 1
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    scene.render.filepath = path
    scene.frame_set(frame)
    bpy.ops.render.render(write_still=True)
    return path
