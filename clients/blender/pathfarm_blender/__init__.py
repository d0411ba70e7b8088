"""pathfarm for Blender: submit the open scene to a pathfarm render farm and bring its
frames back into the Image Editor (docs/blender.md)."""

bl_info = {
    "name": "pathfarm",
    "author": "pathfarm",
    "version": (1, 0, 0),
    "blender": (3, 4, 0),
    "location": "Properties > Render > pathfarm",
    "description": "Render the scene's animation on a pathfarm farm (or a local one) and load the frames",
    "category": "Render",
}

if "bpy" in locals():  # reloaded by Blender (F3 > Reload Scripts)
    import importlib

    for module in (properties, farm_client, scene_export, operators, panel):  # noqa: F821
        importlib.reload(module)
else:
    from . import properties, farm_client, scene_export, operators, panel

import bpy  # noqa: E402

_modules = (properties, operators, panel)


def register():
    for module in _modules:
        module.register()


def unregister():
    farm_client.stop_local_farm()
    for module in reversed(_modules):
        module.unregister()
