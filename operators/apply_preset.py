"""Set a tree's style to one of the preset looks without drawing (for scripts; the
sidebar's preset buttons draw the look: blobtree_ink.illustrate with a preset)."""
import bpy

from ..blobtree_nodes.settings import PRESET_TIPS, PRESETS, apply_preset
from .common import context_tree

PRESET_ITEMS = [(k, k.replace("_", " ").title(), PRESET_TIPS[k]) for k in PRESETS]


class BLOBTREE_INK_OT_apply_preset(bpy.types.Operator):
    """Set the tree's style settings to a preset look, without drawing (grid, agents, level of detail and seed stay)"""
    bl_idname = "blobtree_ink.apply_preset"
    bl_label = "Apply Illustration Preset"
    bl_options = {"REGISTER", "UNDO"}

    tree_name: bpy.props.StringProperty(name="Tree", options={"SKIP_SAVE"},
                                        description="The BlobTree node tree (empty: the active one)")
    preset: bpy.props.EnumProperty(name="Preset", items=PRESET_ITEMS, options={"SKIP_SAVE"}, description="The look")

    def execute(self, context):
        try:
            tree = context_tree(context, self.tree_name)
        except LookupError as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        apply_preset(tree.ink, self.preset)
        return {"FINISHED"}


classes = (BLOBTREE_INK_OT_apply_preset,)
