"""The pathfarm panel in the Render properties."""

import bpy

from . import operators


class RENDER_PT_pathfarm(bpy.types.Panel):
    bl_label = "pathfarm"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "render"

    def draw(self, context):
        layout = self.layout
        settings, state = context.scene.pathfarm, operators.job_state(context)
        layout.use_property_split = True
        layout.prop(settings, "farm")
        if settings.farm == "LOCAL":
            layout.prop(settings, "workers")
        else:
            layout.prop(settings, "scheduler")
            layout.prop(settings, "token_file")
        layout.prop(settings, "executable")
        layout.prop(settings, "pipeline")
        layout.prop(settings, "spp")
        layout.prop(settings, "max_depth")
        layout.prop(settings, "preview_every")
        layout.prop(settings, "reference")
        layout.prop(settings, "output")
        render, scene = context.scene.render, context.scene
        scale = render.resolution_percentage / 100
        layout.label(text=f"{scene.frame_start}–{scene.frame_end}, {round(render.resolution_x * scale)}×"
                          f"{round(render.resolution_y * scale)}, {render.fps / render.fps_base:g} fps")
        row = layout.row()
        row.operator("pathfarm.submit", text="Submit", icon="RENDER_ANIMATION")
        row.operator("pathfarm.cancel", icon="CANCEL")
        if state.status:
            layout.label(text=state.status, icon="ERROR" if state.status.startswith(("failed", "pathfarm")) else "INFO")
        if state.running:
            layout.prop(state, "progress", slider=True)
        if state.folder:
            row = layout.row()
            for file, label in (("report.md", "Report"), ("contact_sheet.png", "Contact sheet"), ("", "Folder")):
                row.operator("pathfarm.open", text=label).file = file
        if len(state.warnings):
            box = layout.box()
            box.label(text="Not carried to pathfarm:", icon="ERROR")
            for warning in state.warnings:
                box.label(text=warning.text)


def register():
    bpy.utils.register_class(RENDER_PT_pathfarm)


def unregister():
    bpy.utils.unregister_class(RENDER_PT_pathfarm)
