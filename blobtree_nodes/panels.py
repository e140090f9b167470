"""The node editor sidebar's Errors panel (Node tab) for BlobTree trees: the active
node's whole error, wrapped to the sidebar's width, and the tree's other nodes with an
error, each a button that makes it the active node and frames it."""
import bpy

from . import wrap
from .base import SHOW_ERROR, draw_error, in_blobtree_editor


def nodes_with_errors(tree):
    return [n for n in tree.nodes if getattr(n, "error", "")]


class NODE_PT_blobtree_ink_errors(bpy.types.Panel):
    """Why the BlobTree cannot be compiled: the error of the active node, the nodes with one"""
    bl_label = "Errors"
    bl_space_type = "NODE_EDITOR"
    bl_region_type = "UI"
    bl_category = "Node"

    @classmethod
    def poll(cls, context):
        return in_blobtree_editor(context) and context.space_data.edit_tree is not None

    def draw(self, context):
        layout = self.layout
        tree = context.space_data.edit_tree
        active = context.active_node
        broken = nodes_with_errors(tree)
        if active in broken:
            layout.label(text=active.name, icon="NODE")
            draw_error(layout, context, active, wrap.region_text_width(context, context.region.width))
        others = [n for n in broken if n != active]
        if others:
            col = layout.column(align=True)
            col.label(text="Nodes with an error:" if active not in broken else "Other nodes with an error:")
            for n in others:
                op = col.operator(SHOW_ERROR, text=n.name, icon="ERROR")
                op.tree_name = tree.name
                op.node_name = n.name
                op.frame = True
        if not broken:
            layout.label(text="No node has an error", icon="CHECKMARK")


classes = (NODE_PT_blobtree_ink_errors,)
