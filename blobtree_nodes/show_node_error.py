"""The error icon of a BlobTree node: its tooltip is the node's whole error; a click
makes the node the active one (the sidebar's Errors panel then shows its error),
frames it when asked to (in the node editor clicked in, or one showing its tree), and
repeats the error in the status bar."""
import bpy

from .base import SHOW_ERROR, TREE


def target_node(properties):
    """The node an operator's tree_name and node_name name, or None."""
    tree = bpy.data.node_groups.get(properties.tree_name)
    if tree is None or tree.bl_idname != TREE:
        return None
    return tree.nodes.get(properties.node_name)


def editor_of(context, tree):
    """The node editor to frame the node in: the one clicked in, else one of the window
    that shows the tree (None: no editor shows it)."""
    areas = [context.area] if context.area is not None else []
    if context.window is not None:
        areas += [a for a in context.window.screen.areas if a != context.area]
    for a in areas:
        if a.type == "NODE_EDITOR" and a.spaces.active.edit_tree == tree:
            return a
    return None


class BLOBTREE_INK_OT_show_node_error(bpy.types.Operator):
    """Why the tree cannot be compiled at this node"""
    bl_idname = SHOW_ERROR
    bl_label = "Node Error"
    bl_options = {"INTERNAL"}

    tree_name: bpy.props.StringProperty(name="Tree", description="The BlobTree node tree of the node")
    node_name: bpy.props.StringProperty(name="Node", description="The node whose error is shown")
    frame: bpy.props.BoolProperty(name="Frame", default=False,
                                  description="Also zoom a node editor showing the tree to the node")

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
        area = editor_of(context, tree) if self.frame else None
        if area is not None:
            region = next(r for r in area.regions if r.type == "WINDOW")
            with context.temp_override(area=area, region=region, space_data=area.spaces.active):
                bpy.ops.node.view_selected()
        if node.error:
            self.report({"WARNING"}, f"{node.name}: {node.error}")
        return {"FINISHED"}


classes = (BLOBTREE_INK_OT_show_node_error,)
