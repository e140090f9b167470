"""File > Import > BlobTree (.json): a blobtree-1 model as a new node tree."""
import time

import bpy
from bpy_extras.io_utils import ImportHelper

from ..blobtree_nodes import changes, preview
from ..blobtree_nodes.build import build_tree
from ..model import ModelError, load
from .common import TREE, show_in_node_editor


class BLOBTREE_INK_OT_import_json(bpy.types.Operator, ImportHelper):
    """Import a BlobTree model (blobtree-1 JSON) as a node tree"""
    bl_idname = "blobtree_ink.import_json"
    bl_label = "Import BlobTree"          # (the file browser's button: short enough to show whole)
    bl_options = {"REGISTER", "UNDO"}

    filename_ext = ".json"
    filter_glob: bpy.props.StringProperty(default="*.json", options={"HIDDEN"})
    preview: bpy.props.BoolProperty(name="Build Preview", default=True,
                                    description="Polygonise a preview mesh right away")

    def execute(self, context):
        try:
            model = load(self.filepath)           # validates everything before any change
        except ModelError as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        with changes.hold():                      # the whole import is one edit of the tree
            tree = bpy.data.node_groups.new(model.name, TREE)
            tree.use_fake_user = True             # saved with the file though nothing uses it
            try:
                build_tree(tree, model)
            except Exception:
                bpy.data.node_groups.remove(tree)     # nothing half-made stays behind
                raise
            tree.show_preview = self.preview
        if self.preview:
            obj = preview.place_beside(tree, model)
            for o in context.view_layer.objects:
                o.select_set(o == obj)
            context.view_layer.objects.active = obj
            if bpy.app.background:          # no timers tick there: build it now
                preview.rebuild(tree)
            else:                           # the UI builds it right after the import, then frames it
                changes.schedule(tree, delay=0.05)
                frame_when_built(context.window, tree.name)
        show_in_node_editor(context, tree)
        self.report({"INFO"}, f"Imported '{tree.name}' ({len(tree.nodes)} nodes)")
        return {"FINISHED"}


FRAME_WAIT = 20.0            # seconds the view waits for a new preview to frame it


def frame_when_built(window, tree_name):
    """Frame the 3D viewports of the window on the tree's preview once it has been built
    (the UI builds it right after the import)."""
    if window is None:
        return
    t0 = time.monotonic()

    def frame():
        tree = bpy.data.node_groups.get(tree_name)
        obj = tree.preview_object if tree is not None else None
        if obj is None or time.monotonic() - t0 > FRAME_WAIT or window.screen is None:
            return None
        if not len(obj.data.polygons):
            return 0.1
        for area in window.screen.areas:
            if area.type == "VIEW_3D" and obj.select_get():
                region = next(r for r in area.regions if r.type == "WINDOW")
                with bpy.context.temp_override(window=window, area=area, region=region):
                    bpy.ops.view3d.view_selected()
        return None
    bpy.app.timers.register(frame, first_interval=0.1)


def menu_func(self, context):
    self.layout.operator(BLOBTREE_INK_OT_import_json.bl_idname, text="BlobTree (.json)")


classes = (BLOBTREE_INK_OT_import_json,)
