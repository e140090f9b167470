"""File > Import > BlobTree (.json): a blobtree-1 model as a new node tree."""
import bpy
from bpy_extras.io_utils import ImportHelper

from ..blobtree_nodes import changes, preview
from ..blobtree_nodes.build import build_tree
from ..model import ModelError, load
from .common import TREE, show_in_node_editor


class BLOBTREE_INK_OT_import_json(bpy.types.Operator, ImportHelper):
    """Import a BlobTree model (blobtree-1 JSON) as a node tree"""
    bl_idname = "blobtree_ink.import_json"
    bl_label = "Import BlobTree (.json)"
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
            if bpy.app.background:          # no timers tick there: build it now
                preview.rebuild(tree)
            else:                           # the UI builds it right after the import
                changes.schedule(tree, delay=0.05)
        show_in_node_editor(context, tree)
        self.report({"INFO"}, f"Imported '{tree.name}' ({len(tree.nodes)} nodes)")
        return {"FINISHED"}


def menu_func(self, context):
    self.layout.operator(BLOBTREE_INK_OT_import_json.bl_idname, text="BlobTree (.json)")


classes = (BLOBTREE_INK_OT_import_json,)
