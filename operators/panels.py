"""Sidebar panels (3D viewport and node editor): requests, settings, the last run's
figures and the Grease Pencil layers' visibility."""
import bpy

from ..blobtree_nodes.settings import PRESETS
from .common import blobtrees
from .illustrate import REQUESTS, last_run


def _draw(layout, context, trees):
    for tree in trees:
        box = layout.box()
        box.label(text=tree.name, icon="META_BALL")
        col = box.column(align=True)
        for ident, label, _ in REQUESTS:
            op = col.operator("blobtree_ink.illustrate", text=label)
            op.tree_name = tree.name
            op.request = ident
        s = tree.ink
        grid = box.grid_flow(columns=2, align=True)
        for key in PRESETS:
            op = grid.operator("blobtree_ink.apply_preset", text=key.replace("_", " ").title())
            op.tree_name = tree.name
            op.preset = key
        col = box.column(align=True)
        col.prop(s, "grid_resolution")
        col.prop(s, "agents")
        col.prop(s, "lod")
        col.prop(s, "seed")
        col.prop(s, "use_camera")
        _draw_style(box, s)
        box.prop(s, "region_radius")
        obj = bpy.data.objects.get(f"{tree.model_name or tree.name} Ink")
        if obj is not None and obj.type == "GREASEPENCIL":
            col = box.column(align=True)
            col.label(text="Layers")
            for layer in obj.data.layers:
                col.prop(layer, "hide", text=layer.name, invert_checkbox=True)
    if last_run:
        col = layout.column(align=True)
        col.label(text=f"Last run: {last_run.get('state', '')}")
        col.label(text=f"Done: {100 * last_run.get('fraction', 0.0):.0f} % ({last_run.get('stage', '')})")
        col.label(text=f"Iterations: {last_run.get('iterations', 0)}")
        col.label(text=f"Outline length: {last_run.get('outline_length', 0):.3g}")


def _draw_style(layout, s):
    col = layout.column(align=True)
    col.label(text="Strokes")
    row = col.row(align=True)
    row.prop(s, "hatching", toggle=True)
    row.prop(s, "stipples", toggle=True)
    row = col.row(align=True)
    row.prop(s, "chains", toggle=True)
    row.prop(s, "short", toggle=True)
    col = layout.column(align=True)
    col.prop(s, "hatch_field")
    if "AXIS" in (s.hatch_field, s.cross_field):
        col.prop(s, "hatch_axis")
    col.prop(s, "cross_hatching")
    if s.cross_hatching:
        col.prop(s, "cross_field")
    col.prop(s, "surface")
    col.prop(s, "weights")
    if s.weights == "CUSTOM":
        for name in ("w_flow", "w_wander", "w_separation", "w_alignment", "w_cohesion", "w_containment"):
            col.prop(s, name)
    col.prop(s, "flock_size")
    col = layout.column(align=True)
    col.prop(s, "shade_lower")
    col.prop(s, "shade_upper")
    col.prop(s, "chain_step")
    col.prop(s, "chain_angle")
    col.prop(s, "stipple_every")
    col.prop(s, "line_width")
    col.prop(s, "contrast")


class VIEW3D_PT_blobtree_ink(bpy.types.Panel):
    bl_label = "BlobTree Ink"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "BlobTree Ink"

    def draw(self, context):
        trees = blobtrees()
        if not trees:
            self.layout.operator("blobtree_ink.import_json", icon="IMPORT")
        _draw(self.layout, context, trees)


class NODE_PT_blobtree_ink(bpy.types.Panel):
    bl_label = "BlobTree Ink"
    bl_space_type = "NODE_EDITOR"
    bl_region_type = "UI"
    bl_category = "BlobTree Ink"

    @classmethod
    def poll(cls, context):
        return getattr(context.space_data, "tree_type", "") == "BlobTreeInkNodeTree"

    def draw(self, context):
        tree = context.space_data.node_tree
        if tree is not None:
            _draw(self.layout, context, [tree])


classes = (VIEW3D_PT_blobtree_ink, NODE_PT_blobtree_ink)
