"""File > Export > BlobTree (.json): a node tree as a blobtree-1 model."""
import bpy
from bpy_extras.io_utils import ExportHelper

from ..blobtree_nodes.compile import TreeError, compile_tree
from ..model import save
from .common import context_tree


class BLOBTREE_INK_OT_export_json(bpy.types.Operator, ExportHelper):
    """Export a BlobTree node tree as a blobtree-1 JSON model"""
    bl_idname = "blobtree_ink.export_json"
    bl_label = "Export BlobTree"          # (the file browser's button: short enough to show whole)

    filename_ext = ".json"
    filter_glob: bpy.props.StringProperty(default="*.json", options={"HIDDEN"})
    tree_name: bpy.props.StringProperty(name="Tree", options={"SKIP_SAVE"},
                                        description="The BlobTree node tree to export (default: the one in the "
                                                    "node editor, or the only one)")

    def execute(self, context):
        try:
            tree = context_tree(context, self.tree_name)
            model = compile_tree(tree)
        except (LookupError, TreeError) as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        try:
            save(model, self.filepath)            # atomic: a failed write keeps the old file
        except OSError as e:
            self.report({"ERROR"}, f"cannot write {self.filepath}: {e.strerror or e}")
            return {"CANCELLED"}
        self.report({"INFO"}, f"Exported '{tree.name}' to {self.filepath}")
        return {"FINISHED"}


def menu_func(self, context):
    self.layout.operator(BLOBTREE_INK_OT_export_json.bl_idname, text="BlobTree (.json)")


classes = (BLOBTREE_INK_OT_export_json,)
