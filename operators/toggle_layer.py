"""Show or hide one layer of a tree's ink (Grease Pencil) object, from the sidebar."""
import bpy

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


class BLOBTREE_INK_OT_toggle_layer(bpy.types.Operator):
    """Show or hide a layer of the ink"""
    bl_idname = "blobtree_ink.toggle_layer"
    bl_label = "Show or Hide Ink Layer"
    bl_options = {"REGISTER", "UNDO"}

    object_name: bpy.props.StringProperty(name="Ink Object", description="The Grease Pencil object")
    layer: bpy.props.StringProperty(name="Layer", description="The layer to show or hide")

    @classmethod
    def description(cls, context, properties):
        what = LAYER_TIPS.get(properties.layer, f"The {properties.layer} layer")
        return f"Show or hide this layer. {what}"

    def execute(self, context):
        obj = bpy.data.objects.get(self.object_name)
        layer = obj.data.layers.get(self.layer) if obj is not None and obj.type == "GREASEPENCIL" else None
        if layer is None:
            self.report({"ERROR"}, f"no ink layer '{self.layer}' on '{self.object_name}'")
            return {"CANCELLED"}
        layer.hide = not layer.hide
        return {"FINISHED"}


classes = (BLOBTREE_INK_OT_toggle_layer,)
