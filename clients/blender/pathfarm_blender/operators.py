"""Submit, Cancel and Open Report, and the timer that follows the shot in flight."""

import os

import bpy

from . import farm_client, scene_export
from .farm_client import FarmError

POLL_SECONDS = 0.5
_job = None  # the shot in flight (farm_client.ShotJob), one per Blender session


def job_state(context):
    return context.window_manager.pathfarm_job


def start_shot(context):
    """Exports the scene, starts the farm if it is local, submits; returns the ShotJob.
    Raises FarmError with a message for the artist."""
    global _job
    settings = context.scene.pathfarm
    if _job and not _job.finished():
        raise FarmError(f"shot {_job.shot_id} is still running: cancel it first")
    if not bpy.data.filepath and settings.output.startswith("//"):
        raise FarmError("save the .blend first, or give the output an absolute folder")
    executable = farm_client.find_executable(bpy.path.abspath(settings.executable))
    folder = os.path.abspath(bpy.path.abspath(settings.output))
    shot_file, warnings = scene_export.export_shot(context, os.path.join(folder, "shot"))
    if settings.farm == "LOCAL":
        connection = farm_client.local_farm(executable, os.path.join(folder, "farm"), settings.workers).connection()
    else:
        connection = farm_client.Connection(executable, settings.scheduler, settings.token_file)
    _job = farm_client.ShotJob(connection, shot_file, folder)
    state = job_state(context)
    state.running, state.progress, state.status, state.folder = True, 0.0, _job.message, folder
    state.warnings.clear()
    for text in warnings:
        state.warnings.add().text = text
    return _job


def update_state(context):
    """Polls the job into the panel's state; loads the frames once it is done. Returns
    whether the job is still running."""
    if _job is None:
        return False
    _job.poll()
    state = job_state(context)
    state.status, state.progress, state.shot_id = _job.message, _job.progress, _job.shot_id
    if _job.finished():
        state.running = False
        if _job.state == "done":
            load_frames(_job.frames(), f"pathfarm shot {_job.shot_id}")
    for area in context.screen.areas if context.screen else []:
        if area.type == "PROPERTIES":
            area.tag_redraw()
    return not _job.finished()


def load_frames(frames, name):
    """The frames as one image sequence, shown in every Image Editor."""
    if not frames:
        return None
    image = bpy.data.images.load(frames[0], check_existing=False)
    image.name = name
    image.source = "SEQUENCE" if len(frames) > 1 else "FILE"
    first = int(os.path.basename(frames[0])[6:-4])
    for window in getattr(bpy.context.window_manager, "windows", []):
        for area in window.screen.areas:
            if area.type == "IMAGE_EDITOR":
                space = area.spaces.active
                space.image = image
                space.image_user.frame_duration = len(frames)
                space.image_user.frame_start = first
                space.image_user.frame_offset = first - 1
                space.image_user.use_auto_refresh = True
    return image


def _timer():
    try:
        running = update_state(bpy.context)
    except FarmError as error:
        job_state(bpy.context).status, job_state(bpy.context).running = str(error), False
        return None
    bpy.context.workspace.status_text_set(job_state(bpy.context).status if running else None)
    return POLL_SECONDS if running else None


class PATHFARM_OT_submit(bpy.types.Operator):
    bl_idname = "pathfarm.submit"
    bl_label = "Submit to pathfarm"
    bl_description = "Export the scene, submit its animation as a shot and bring the frames back"

    def execute(self, context):
        try:
            job = start_shot(context)
        except (FarmError, OSError) as error:
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        for warning in job_state(context).warnings:
            self.report({"WARNING"}, warning.text)
        self.report({"INFO"}, f"pathfarm: {job.message}")
        if not bpy.app.timers.is_registered(_timer):
            bpy.app.timers.register(_timer, first_interval=POLL_SECONDS)
        return {"FINISHED"}


class PATHFARM_OT_cancel(bpy.types.Operator):
    bl_idname = "pathfarm.cancel"
    bl_label = "Cancel"
    bl_description = "Cancel the shot on the farm"

    @classmethod
    def poll(cls, context):
        return _job is not None and not _job.finished()

    def execute(self, context):
        try:
            _job.cancel()
        except FarmError as error:
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        update_state(context)
        return {"FINISHED"}


class PATHFARM_OT_open(bpy.types.Operator):
    bl_idname = "pathfarm.open"
    bl_label = "Open"
    bl_description = "Open a file of the last shot"

    file: bpy.props.EnumProperty(items=[("report.md", "Report", ""), ("contact_sheet.png", "Contact sheet", ""),
                                        ("", "Folder", "")])

    def execute(self, context):
        path = os.path.join(job_state(context).folder, "frames", self.file)
        if not os.path.exists(path):
            self.report({"ERROR"}, f"{path} does not exist (yet)")
            return {"CANCELLED"}
        bpy.ops.wm.path_open(filepath=path)
        return {"FINISHED"}


_classes = (PATHFARM_OT_submit, PATHFARM_OT_cancel, PATHFARM_OT_open)


def register():
    for cls in _classes:
        bpy.utils.register_class(cls)


def unregister():
    if bpy.app.timers.is_registered(_timer):
        bpy.app.timers.unregister(_timer)
    for cls in reversed(_classes):
        bpy.utils.unregister_class(cls)
