"""The error icon of a BlobTree node: its tooltip is the node's whole error; a click
makes the node the active one (the sidebar's Errors panel then shows its error),
frames it when asked to, and repeats the error in the status bar."""
import bpy

from .base import SHOW_ERROR, TREE


def target_node(properties):
    """The node an operator's tree_name and node_name name, or None."""
    tree = bpy.data.node_groups.get(properties.tree_name)
    if tree is None or tree.bl_idname != TREE:
        return None
    return tree.nodes.get(properties.node_name)


class BLOBTREE_INK_OT_show_node_error(bpy.types.Operator):
    """Why the tree cannot be compiled at this node"""
    bl_idname = SHOW_ERROR
    bl_label = "Node Error"
    bl_options = {"INTERNAL"}

    tree_name: bpy.props.StringProperty(name="Tree", description="The BlobTree node tree of the node")
    node_name: bpy.props.StringProperty(name="Node", description="The node whose error is shown")
    frame: bpy.props.BoolProperty(name="Frame", default=False,
                                  description="Also zoom the node editor to the node")

    @classmethod
    def description(cls, context, properties):
        node = target_node(properties)
        if node is None or not node.error:
            return None                      # the docstring
        return f"{node.name}: {node.error}"

    def execute(self, context):
        node = target_node(self)
        if node is None:
            self.report({"WARNING"}, f"BlobTree '{self.tree_name}' has no node '{self.node_name}'")
            return {"CANCELLED"}
        tree = node.id_data
        for n in tree.nodes:
            if n.select != (n == node):
                n.select = n == node
        tree.nodes.active = node
        area = context.area
        if self.frame and area is not None and area.type == "NODE_EDITOR":
            region = next(r for r in area.regions if r.type == "WINDOW")
            with context.temp_override(area=area, region=region):
                bpy.ops.node.view_selected()
        if node.error:
            self.report({"WARNING"}, f"{node.name}: {node.error}")
        return {"FINISHED"}


classes = (BLOBTREE_INK_OT_show_node_error,)
