"""Rebuild a BlobTree's preview mesh now (also reports a broken tree's error)."""
import bpy

from ..blobtree_nodes import preview
from ..blobtree_nodes.compile import TreeError, compile_tree
from .common import context_tree


class BLOBTREE_INK_OT_rebuild_preview(bpy.types.Operator):
    """Compile the tree and polygonise its preview mesh now"""
    bl_idname = "blobtree_ink.rebuild_preview"
    bl_label = "Rebuild Preview"
    bl_options = {"REGISTER", "UNDO"}

    tree_name: bpy.props.StringProperty(name="Tree", options={"SKIP_SAVE"})

    def execute(self, context):
        try:
            tree = context_tree(context, self.tree_name)
            compile_tree(tree)
        except (LookupError, TreeError) as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        if not tree.show_preview:
            tree.show_preview = True
        if not preview.rebuild(tree):
            self.report({"ERROR"}, "the preview could not be built (see the Model Output node)")
            return {"CANCELLED"}
        return {"FINISHED"}


classes = (BLOBTREE_INK_OT_rebuild_preview,)
