"""The add-on's settings, saved with the .blend (Scene), and the state of the shot in
flight, which is not (WindowManager)."""

import bpy
from bpy.props import BoolProperty, CollectionProperty, EnumProperty, FloatProperty, IntProperty, StringProperty

PIPELINES = [
    ("auto", "Auto", "A probe on the farm picks the cheapest pipeline at equal error"),
    ("dui", "Denoise, upsample, interpolate", "Keyframes at low resolution, in-betweens interpolated"),
    ("di", "Denoise, interpolate", "Keyframes at full resolution, in-betweens interpolated"),
    ("du", "Denoise, upsample", "Every frame at low resolution, upsampled and denoised"),
    ("d", "Denoise", "Every frame rendered and denoised per path-space component"),
    ("tgpt", "Temporal gradient-domain", "Gradient-domain path tracing, Poisson reconstruction over time"),
    ("tmlt", "Temporal Metropolis", "Metropolis light transport with chains shared between frames"),
    ("pt", "Path tracing", "Plain path tracing, no filtering"),
]


class PathfarmSettings(bpy.types.PropertyGroup):
    farm: EnumProperty(
        name="Farm",
        items=[
            ("LOCAL", "This computer", "Start a farm of worker processes on this computer"),
            ("REMOTE", "Scheduler", "Submit to a running pathfarm scheduler"),
        ],
        default="LOCAL",
    )
    executable: StringProperty(
        name="pathfarm",
        description="The pathfarm executable (empty: $PATHFARM, else pathfarm on the PATH)",
        subtype="FILE_PATH",
    )
    scheduler: StringProperty(name="Address", description="The scheduler's HOST:PORT", default="127.0.0.1:7700")
    token_file: StringProperty(name="Token file", description="File holding the farm's access token", subtype="FILE_PATH")
    workers: IntProperty(name="Workers", description="Worker processes of the local farm", default=2, min=1, max=256)
    pipeline: EnumProperty(name="Pipeline", items=PIPELINES, default="auto")
    spp: IntProperty(name="Samples", description="Samples per pixel of the plain path-traced budget", default=64, min=1)
    max_depth: IntProperty(
        name="Max depth", description="Scattering events per path (Cycles' total bounces + 1)", default=8, min=1, max=1024
    )
    preview_every: IntProperty(
        name="Preview every",
        description="Render every n-th frame first, for an early review (1: in frame order)",
        default=1,
        min=1,
        max=1000,
    )
    reference: BoolProperty(
        name="Reference", description="Also render references and report every frame's error against them", default=False
    )
    output: StringProperty(
        name="Output", description="Folder of the shot's files and frames", default="//pathfarm/", subtype="DIR_PATH"
    )


class PathfarmWarning(bpy.types.PropertyGroup):
    text: StringProperty()


class PathfarmJobState(bpy.types.PropertyGroup):
    running: BoolProperty(default=False)
    status: StringProperty(default="")
    progress: FloatProperty(name="Progress", default=0, min=0, max=1, subtype="FACTOR")
    shot_id: IntProperty(default=0)
    folder: StringProperty(default="")
    warnings: CollectionProperty(type=PathfarmWarning)


_classes = (PathfarmSettings, PathfarmWarning, PathfarmJobState)


def register():
    for cls in _classes:
        bpy.utils.register_class(cls)
    bpy.types.Scene.pathfarm = bpy.props.PointerProperty(type=PathfarmSettings)
    bpy.types.WindowManager.pathfarm_job = bpy.props.PointerProperty(type=PathfarmJobState)


def unregister():
    del bpy.types.WindowManager.pathfarm_job
    del bpy.types.Scene.pathfarm
    for cls in reversed(_classes):
        bpy.utils.unregister_class(cls)
