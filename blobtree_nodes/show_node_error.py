"""The error icon of a BlobTree node: its tooltip is the node's whole error; a click
makes the node the active one (the sidebar's Errors panel then shows its error),
brings it into view when asked to (in the node editor clicked in, or one showing its
tree), and repeats the error in the status bar."""
import bpy

from .base import SHOW_ERROR, TREE, shown_name


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


READABLE = 0.75        # a node editor zoomed out further than this (pixels per unit) is zoomed to 1:1


def bring_into_view(context, area, node):
    """Pan the node editor so that the node's centre is in the middle of what shows of
    it (its sidebar and toolbar, drawn over the editor, cover a part: the editor's own
    View Selected centres on the whole and can leave the node under the sidebar), zoomed
    in to 1:1 first when it is zoomed out so far that a node cannot be read (View
    Selected never zooms in on one node)."""
    region = next(r for r in area.regions if r.type == "WINDOW")
    zoom = (region.view2d.view_to_region(1000.0, 0.0, clip=False)[0]
            - region.view2d.view_to_region(0.0, 0.0, clip=False)[0]) / 1000.0
    if 0 < zoom < READABLE:
        with context.temp_override(area=area, region=region, space_data=area.spaces.active):
            bpy.ops.view2d.zoom_in(zoomfacx=(1 - zoom) / 2, zoomfacy=(1 - zoom) / 2)
    left, right = region.x, region.x + region.width
    for r in area.regions:
        if r.type in ("UI", "TOOLS") and r.width > 1 and left < r.x + r.width and r.x < right:
            if r.x + r.width / 2 > region.x + region.width / 2:
                right = min(right, r.x)                  # drawn over the right of the editor
            else:
                left = max(left, r.x + r.width)
    scale = context.preferences.system.ui_scale or 1.0
    at = getattr(node, "location_absolute", node.location)  # (inside a frame, its own location is relative)
    x, y = region.view2d.view_to_region(at.x * scale + node.dimensions.x / 2, at.y * scale - node.dimensions.y / 2,
                                        clip=False)
    dx, dy = region.x + x - (left + right) / 2, y - region.height / 2
    with context.temp_override(area=area, region=region, space_data=area.spaces.active):
        bpy.ops.view2d.pan(deltax=round(dx), deltay=round(dy))


class BLOBTREE_INK_OT_show_node_error(bpy.types.Operator):
    """Why the tree cannot be compiled at this node"""
    bl_idname = SHOW_ERROR
    bl_label = "Node Error"
    bl_options = {"INTERNAL"}

    tree_name: bpy.props.StringProperty(name="Tree", options={"SKIP_SAVE"},
                                        description="The BlobTree node tree of the node")
    node_name: bpy.props.StringProperty(name="Node", options={"SKIP_SAVE"}, description="The node whose error is shown")
    frame: bpy.props.BoolProperty(name="Frame", default=False, options={"SKIP_SAVE"},
                                  description="Also zoom a node editor showing the tree to the node")

    @classmethod
    def description(cls, context, properties):
        node = target_node(properties)
        if node is None or not node.error:
            return None                      # the docstring
        return f"{shown_name(node)}: {node.error}"

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
            bring_into_view(context, area, node)
        if node.error:
            self.report({"WARNING"}, f"{shown_name(node)}: {node.error}")
        return {"FINISHED"}


classes = (BLOBTREE_INK_OT_show_node_error,)
