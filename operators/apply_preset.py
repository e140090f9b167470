"""Apply one of the illustration presets (the looks of the papers' figures) to a tree."""
import bpy

from ..blobtree_nodes.settings import PRESETS
from .common import context_tree


class BLOBTREE_INK_OT_apply_preset(bpy.types.Operator):
    """Set the tree's illustration settings to a preset"""
    bl_idname = "blobtree_ink.apply_preset"
    bl_label = "Apply Illustration Preset"
    bl_options = {"REGISTER", "UNDO"}

    tree_name: bpy.props.StringProperty(name="Tree")
    preset: bpy.props.EnumProperty(name="Preset", items=[(k, k.replace("_", " ").title(), f"The {k.lower().replace('_', ' ')} look")
                                                 for k in PRESETS])

    def execute(self, context):
        try:
            tree = context_tree(context, self.tree_name)
        except LookupError as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        for key, value in PRESETS[self.preset].items():
            setattr(tree.ink, key, value)
        return {"FINISHED"}


classes = (BLOBTREE_INK_OT_apply_preset,)
