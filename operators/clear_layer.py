"""Clear one layer of a tree's ink (Grease Pencil) object at the current frame, from the
sidebar's Ink Layers: what a look or a request drew there goes, the other layers and
frames stay (one undo step)."""
import bpy

from ..grease_pencil import views
from .common import InkLayerOperator


class BLOBTREE_INK_OT_clear_layer(InkLayerOperator, bpy.types.Operator):
    """Remove the strokes of a layer of the ink at this frame"""
    bl_idname = "blobtree_ink.clear_layer"
    bl_label = "Clear Ink Layer"
    bl_options = {"REGISTER", "UNDO"}
    tip = "Remove this layer's strokes at this frame (its drawing held here)"

    def act(self, context, layer):
        key = views.shown_frame(layer, context.scene.frame_current)
        n = len(key.drawing.strokes) if key is not None else 0
        if n:
            key.drawing.remove_strokes()
            views.forget(bpy.data.objects[self.object_name], [self.layer], key.frame_number)
        self.report({"INFO"}, f"cleared {n} stroke{'s' if n != 1 else ''} of {self.layer}" if n
                    else f"{self.layer} has no stroke at this frame")
        return {"FINISHED"}


classes = (BLOBTREE_INK_OT_clear_layer,)
