"""Show or hide one layer of a tree's ink (Grease Pencil) object, from the sidebar."""
import bpy

from .common import InkLayerOperator


class BLOBTREE_INK_OT_toggle_layer(InkLayerOperator, bpy.types.Operator):
    """Show or hide a layer of the ink"""
    bl_idname = "blobtree_ink.toggle_layer"
    bl_label = "Show or Hide Ink Layer"
    bl_options = {"REGISTER", "UNDO"}
    tip = "Show or hide this layer"

    def act(self, context, layer):
        layer.hide = not layer.hide
        return {"FINISHED"}


classes = (BLOBTREE_INK_OT_toggle_layer,)
