"""Show or hide one layer of a tree's ink (Grease Pencil) object, from the sidebar."""
import bpy

from .common import InkLayerOperator

LAYER_TIPS = {
    "Silhouette": "The silhouettes: where the surface turns away from the eye",
    "Crease": "The creases: where unions, intersections and differences meet",
    "Curvature": "Curvature-sign lines: where the surface turns from convex to concave",
    "Suggestive": "Suggestive contours: where the surface comes closest to turning away from the eye",
    "Ridges": "Apparent ridges: the crests where the surface, as seen, bends most sharply",
    "Hatching": "Hatching and cross-hatching in the shade",
    "Chains": "Strokes started from the silhouette and crease chains",
    "Short Strokes": "Short strokes through points spread over the shaded surface",
    "Stipples": "Stipples in the shade",
    "Single Strokes": "The single strokes drawn from the 3D cursor",
}


def layer_tip(layer):
    """What a layer of the ink holds, for tooltips."""
    return LAYER_TIPS.get(layer, f"The {layer} layer")


class BLOBTREE_INK_OT_toggle_layer(InkLayerOperator, bpy.types.Operator):
    """Show or hide a layer of the ink"""
    bl_idname = "blobtree_ink.toggle_layer"
    bl_label = "Show or Hide Ink Layer"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def description(cls, context, properties):
        return f"Show or hide this layer. {layer_tip(properties.layer)}"

    def execute(self, context):
        layer = self.ink_layer()
        if layer is None:
            return {"CANCELLED"}
        layer.hide = not layer.hide
        return {"FINISHED"}


classes = (BLOBTREE_INK_OT_toggle_layer,)
