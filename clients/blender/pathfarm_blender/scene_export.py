"""The open scene as pathfarm reads it: a glTF file from Blender's own exporter, a JSON
scene that includes it and adds what glTF cannot carry (the World, the frame rate, the
shutter, the render settings), and a shot file. What glTF drops is listed as warnings."""

import json
import os

import bpy

from .farm_client import FarmError

# Principled BSDF inputs that the glTF file (or pathfarm's reading of it) does not carry,
# each by its Blender 3.x name and, where 4.0 renamed it, its new one.
DROPPED_PRINCIPLED_INPUTS = (("Subsurface", "Subsurface Weight"), ("Sheen", "Sheen Weight"),
                             ("Clearcoat", "Coat Weight"), ("Anisotropic",))


def principled_input(node, names):
    return next((node.inputs[name] for name in names if name in node.inputs), None)


def check_scene(scene):
    """Raises FarmError for what cannot be rendered; returns warnings for what is lost."""
    if scene.camera is None:
        raise FarmError("the scene has no active camera")
    if scene.camera.data.type != "PERSP":
        raise FarmError(f"camera {scene.camera.name}: pathfarm renders perspective cameras only")
    warnings = []
    for obj in scene.objects:
        if obj.type == "LIGHT" and obj.data.type == "AREA":
            warnings.append(f"area light {obj.name}: glTF has none; use a mesh with an emissive material")
        if obj.type == "VOLUME" or any(m.type == "PARTICLE_SYSTEM" for m in getattr(obj, "modifiers", [])):
            warnings.append(f"{obj.name}: volumes and particle systems are not exported to glTF")
    for material in bpy.data.materials:
        if material.users and material.use_nodes:
            warnings += material_warnings(material)
    if scene.render.use_motion_blur and scene.render.motion_blur_position != "START":
        warnings.append("motion blur: the shutter opens on the frame in pathfarm (Blender's Start on Frame); "
                        f"'{scene.render.motion_blur_position.title()}' is rendered as Start")
    world_environment(scene, warnings)
    return warnings


def material_warnings(material):
    warnings = []
    output = material.node_tree.get_output_node("ALL")
    surface = output.inputs["Surface"].links[0].from_node if output and output.inputs["Surface"].links else None
    if surface is None:
        return [f"material {material.name}: no surface shader; it renders as glTF's default"]
    if surface.type not in ("BSDF_PRINCIPLED", "EMISSION"):
        warnings.append(f"material {material.name}: a {surface.bl_label} node; glTF carries only the Principled BSDF "
                        "and Emission (the exporter guesses the rest)")
    if output.inputs["Volume"].links:
        warnings.append(f"material {material.name}: its volume shader is not exported")
    if emits(surface) and not material.use_backface_culling:
        warnings.append(f"material {material.name}: emits from both sides in Blender, from the front face only "
                        "in pathfarm (turn on Backface Culling to see it as pathfarm will)")
    if surface.type == "BSDF_PRINCIPLED":
        for names in DROPPED_PRINCIPLED_INPUTS:
            socket = principled_input(surface, names)
            if socket is not None and (socket.links or socket.default_value > 0):
                warnings.append(f"material {material.name}: Principled {names[0]} is not rendered by pathfarm")
    return warnings


def emits(surface):
    principled = surface.type == "BSDF_PRINCIPLED"
    strength = principled_input(surface, ("Emission Strength",) if principled else ("Strength",))
    color = principled_input(surface, ("Emission", "Emission Color") if principled else ("Color",))
    if strength is None or color is None:
        return False
    return bool(strength.links or color.links) or (strength.default_value > 0 and max(color.default_value[:3]) > 0)


def world_environment(scene, warnings):
    """The World as a pathfarm environment: a constant colour, or an equirectangular image."""
    world = scene.world
    if world is None:
        return None
    if not world.use_nodes:
        return {"radiance": list(world.color)}
    output = world.node_tree.get_output_node("ALL")
    links = output.inputs["Surface"].links if output else []
    background = links[0].from_node if links else None
    if background is None or background.type != "BACKGROUND":
        warnings.append("World: not a Background shader; the sky is black")
        return None
    strength = background.inputs["Strength"].default_value
    color = background.inputs["Color"]
    if not color.links:
        return {"radiance": [c * strength for c in color.default_value[:3]]}
    texture = color.links[0].from_node
    if texture.type == "TEX_ENVIRONMENT" and texture.image is not None and texture.projection == "EQUIRECTANGULAR":
        if texture.inputs["Vector"].links:
            warnings.append("World: the environment texture's mapping is ignored")
        return {"map": bpy.path.abspath(texture.image.filepath), "strength": strength}
    warnings.append(f"World: a {texture.bl_label} node feeds the Background; the sky is black")
    return None


def export_shot(context, folder):
    """Writes scene.glb, scene.json and shot.json into `folder`; returns (shot file, warnings)."""
    scene, settings = context.scene, context.scene.pathfarm
    warnings = check_scene(scene)
    os.makedirs(folder, exist_ok=True)
    glb = os.path.join(folder, "scene.glb")
    export_gltf(glb)
    render = scene.render
    scale = render.resolution_percentage / 100
    shutter = render.motion_blur_shutter if render.use_motion_blur else 0
    scene_json = {
        "include": {"file": "scene.glb", "camera": scene.camera.name, "shutter": [0, min(shutter, 1.0)]},
        "fps": render.fps / render.fps_base,
        "render": {
            "resolution": [round(render.resolution_x * scale), round(render.resolution_y * scale)],
            "spp": settings.spp,
            "max_depth": settings.max_depth,
            "frames": [scene.frame_start, scene.frame_end],
        },
    }
    environment = world_environment(scene, [])
    if environment:
        scene_json["environment"] = environment
    shot = {"name": shot_name(scene), "scene": "scene.json", "pipeline": settings.pipeline, "output": "frames"}
    if settings.preview_every > 1:
        shot["preview_every"] = settings.preview_every
    if settings.reference:
        shot["reference_spp"] = "auto"
    write_json(os.path.join(folder, "scene.json"), scene_json)
    shot_file = os.path.join(folder, "shot.json")
    write_json(shot_file, shot)
    return shot_file, warnings


def shot_name(scene):
    blend = os.path.splitext(os.path.basename(bpy.data.filepath))[0] or "untitled"
    name = f"{blend}-{scene.name}"
    return "".join(c if c.isalnum() or c in "-_." else "_" for c in name)


def export_gltf(path):
    options = dict(filepath=path, export_format="GLB", use_selection=False, export_cameras=True,
                   export_lights=True, export_apply=True, export_animations=True, export_yup=True)
    # Blender 3.4's exporter has a lighting mode; "SPEC" (physical units) is what pathfarm reads.
    if "export_import_convert_lighting_mode" in bpy.ops.export_scene.gltf.get_rna_type().properties:
        options["export_import_convert_lighting_mode"] = "SPEC"
    result = bpy.ops.export_scene.gltf(**options)
    if "FINISHED" not in result or not os.path.exists(path):
        raise FarmError("Blender's glTF exporter wrote no file")


def write_json(path, document):
    with open(path, "w") as file:
        json.dump(document, file, indent=2)
        file.write("\n")
