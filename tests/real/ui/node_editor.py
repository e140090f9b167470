"""Real-UI script: the node editor as an artist meets it. In a fresh BlobTree editor,
with the mouse over it: Shift+A, type "poi", Return, move and click to place: a Point
node, at the click. Then a Model Output with nothing linked, and a Blend linked to it
with nothing linked in: each time the preview's compile puts the error on the node,
and the sidebar's Errors panel (Node tab) shows it whole; hovering the node's error
icon shows it as a tooltip. Then the editor follows the active object's tree (the
pear's preview, made active by an import and again after another object), while a tree
the artist browses to stays until another object is made active; an editor left with
no tree shows the active object's; a pinned one keeps its tree. Screenshots of each
step; facts for the test."""
import os
import sys

import addon_utils
import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from uistep import EXT, REPO, Steps, record  # noqa: E402

TREE = "BlobTreeInkNodeTree"


def region_of(area, kind):
    return next(r for r in area.regions if r.type == kind)


def screen_xy(win, region, x, y):
    """X screen pixels of a point in a region (Blender counts from the window's bottom)."""
    return int(win.x + region.x + x), int(win.y + win.height - (region.y + y))


def blobtree_nodes(tree):
    return sorted(getattr(n, "kind", n.bl_idname) for n in tree.nodes)


def node_view_to_screen(win, region, node, dx, dy):
    """Screen pixels of a point (dx, dy) UI units right of and below a node's top left."""
    s = bpy.context.preferences.system.ui_scale
    x, y = region.view2d.view_to_region((node.location.x + dx) * s, (node.location.y - dy) * s, clip=False)
    return screen_xy(win, region, x, y)


def show_sidebar_node_tab(area):
    area.spaces.active.show_region_ui = True
    yield 0.5                                       # the sidebar has its tabs once drawn
    region_of(area, "UI").active_panel_category = "Node"
    yield 0.5


def run():
    yield 1.0
    yield {"action": "key", "keys": ["Escape"]}          # the splash takes the first Escape
    addon_utils.enable(EXT, default_set=True)
    win = bpy.context.window_manager.windows[0]
    area = max(win.screen.areas, key=lambda a: a.width * a.height)
    area.type = "NODE_EDITOR"
    space = area.spaces.active
    space.tree_type = TREE
    space.show_region_ui = False
    tree = bpy.data.node_groups.new("Sketch", TREE)
    space.node_tree = tree
    yield 1.0
    region = region_of(area, "WINDOW")
    cx, cy = screen_xy(win, region, region.width / 2, region.height / 2)
    record(window=[win.x, win.y, win.width, win.height], editor=[region.x, region.y, region.width, region.height],
           mouse=[cx, cy], nodes_before=blobtree_nodes(tree))
    # --- Shift+A, search, add -------------------------------------------------------
    yield {"action": "mouse", "x": cx, "y": cy}
    yield {"action": "key", "keys": ["shift+a"], "pause": 0.6}
    yield {"action": "type", "text": "poi", "pause": 0.8}
    yield {"action": "screenshot", "name": "node_add_search.png"}
    yield {"action": "key", "keys": ["Return"], "pause": 0.6}
    click = [cx - 200, cy - 120]                          # the new node follows the mouse there
    yield {"action": "mouse", "x": click[0], "y": click[1], "click": 1, "pause": 0.4}
    yield 0.5
    added = [n for n in tree.nodes if getattr(n, "kind", "") == "point"]
    record(nodes_after_add=blobtree_nodes(tree),
           added_is_active=bool(added) and tree.nodes.active == added[0])
    if not added:
        return
    point = added[0]
    record(click=click, point_top_left=list(node_view_to_screen(win, region, point, 0, 0)))
    point.center = (1.1, -2.25, 12.34)
    point.radius = 1.25
    # --- errors ---------------------------------------------------------------------
    out = tree.nodes.new("BlobTreeInkOutputNode")
    out.location = (point.location.x + 260, point.location.y)
    for n in tree.nodes:
        n.select = n == out
    tree.nodes.active = out
    yield from show_sidebar_node_tab(area)
    yield 1.0                                             # the preview's compile marks the node
    panel = sys.modules[EXT + ".blobtree_nodes.panels"].NODE_PT_blobtree_ink_errors
    wrap = sys.modules[EXT + ".blobtree_nodes.wrap"]
    sidebar = region_of(area, "UI")
    with bpy.context.temp_override(window=win, area=area, region=sidebar):
        ctx = bpy.context
        lines = wrap.lines(out.error, wrap.region_text_width(ctx, sidebar.width), ctx)
        record(output_error=out.error, panel_shown=panel.poll(ctx),
               sidebar_category=sidebar.active_panel_category, sidebar_lines=lines,
               sidebar_text_width=wrap.region_text_width(ctx, sidebar.width))
    yield {"action": "screenshot", "name": "node_error_output.png"}
    blend = tree.nodes.new(sys.modules[EXT + ".blobtree_nodes.nodes"].idname("blend"))
    blend.location = (point.location.x + 20, point.location.y - 330)
    tree.links.new(blend.outputs[0], out.inputs[0])
    for n in tree.nodes:
        n.select = n == blend
    tree.nodes.active = blend
    yield 1.5
    record(blend_error=blend.error, output_error_after_link=out.error,
           blend_inputs=[s.name for s in blend.inputs])
    yield {"action": "screenshot", "name": "node_error_blend.png"}
    # --- the error icon's tooltip ---------------------------------------------------
    x, y = node_view_to_screen(win, region, blend, 24, 64)
    record(icon_at=[x, y])
    yield {"action": "mouse", "x": x + 6, "y": y + 4}
    yield {"action": "mouse", "x": x, "y": y, "pause": 2.0}
    yield {"action": "screenshot", "name": "node_error_tooltip.png"}
    record(point_center=[round(v, 4) for v in point.center], point_width=point.width,
           version=bpy.app.version_string, background=bpy.app.background)
    # --- the editor follows the active object's tree --------------------------------
    yield from following_the_active_object(win, area, space, tree)


def shown_after_redraw(area, space):
    area.tag_redraw()
    yield 0.6
    return space.node_tree.name if space.node_tree is not None else None


def following_the_active_object(win, area, space, sketch):
    """The active object picks the editor's tree; browsing picks it until the active
    object changes again."""
    layer = bpy.context.view_layer
    cube = bpy.data.objects.get("Cube")
    with bpy.context.temp_override(window=win, area=area):
        bpy.ops.blobtree_ink.import_json(filepath=os.path.join(REPO, "examples", "pear.json"), preview=True)
    pear = bpy.data.node_groups["pear"]
    record(active_after_import=layer.objects.active.name, shown_after_import=(yield from shown_after_redraw(area, space)))
    space.node_tree = sketch                      # what the editor's browse menu does
    record(shown_after_browse=(yield from shown_after_redraw(area, space)))
    layer.objects.active = cube                   # an object of no tree: the browsed tree stays
    record(shown_with_cube_active=(yield from shown_after_redraw(area, space)))
    layer.objects.active = pear.preview_object
    record(shown_with_pear_active=(yield from shown_after_redraw(area, space)), cube=getattr(cube, "name", None))
    yield {"action": "screenshot", "name": "node_editor_follows.png"}
    space.node_tree = None                        # an editor showing no tree (its browse menu's X)
    record(shown_when_emptied=(yield from shown_after_redraw(area, space)))
    space.node_tree = sketch
    space.pin = True                              # the pin keeps a tree whatever is made active
    layer.objects.active = cube
    yield from shown_after_redraw(area, space)
    layer.objects.active = pear.preview_object
    record(shown_pinned=(yield from shown_after_redraw(area, space)))
    space.pin = False


Steps(run())
