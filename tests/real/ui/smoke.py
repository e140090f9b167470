"""UI smoke test script: the full Blender UI with the extension enabled; an example is
imported through the File > Import operator, its tree shown in a node editor and its
preview mesh in the 3D viewport; the harness takes the screenshot."""
import os
import sys

import addon_utils
import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from uistep import Steps, record  # noqa: E402

EXT = "bl_ext.user_default.blobtree_ink"
REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))


def area_of(screen, kind):
    areas = [a for a in screen.areas if a.type == kind]
    return max(areas, key=lambda a: a.width * a.height) if areas else None


def run():
    yield 1.0
    yield {"action": "key", "keys": ["Escape"]}          # the splash takes the first Escape
    addon_utils.enable(EXT, default_set=True)
    loaded, enabled = addon_utils.check(EXT)
    win = bpy.context.window_manager.windows[0]
    screen = win.screen
    view3d = area_of(screen, "VIEW_3D")
    for obj in list(bpy.data.objects):                    # the default cube would hide the model
        if obj.type == "MESH":
            bpy.data.objects.remove(obj)
    with bpy.context.temp_override(window=win, area=view3d, region=view3d.regions[-1]):
        bpy.ops.screen.area_split(direction="VERTICAL", factor=0.5)
    yield 0.5
    left = min((a for a in screen.areas if a.type == "VIEW_3D"), key=lambda a: a.x)
    left.type = "NODE_EDITOR"
    space = left.spaces.active
    space.tree_type = "BlobTreeInkNodeTree"
    space.show_region_ui = False
    with bpy.context.temp_override(window=win, area=left):
        res = bpy.ops.blobtree_ink.import_json(filepath=os.path.join(REPO, "examples", "pear.json"))
    yield 1.5                                             # the preview is built by its timer
    tree = bpy.data.node_groups.get("pear")
    preview = tree.preview_object if tree else None
    view3d = area_of(screen, "VIEW_3D")
    if preview is not None:
        for o in bpy.context.view_layer.objects:
            o.select_set(o == preview)
        bpy.context.view_layer.objects.active = preview
        region = [r for r in view3d.regions if r.type == "WINDOW"][0]
        with bpy.context.temp_override(window=win, area=view3d, region=region):
            bpy.ops.view3d.view_selected()
    node_region = [r for r in left.regions if r.type == "WINDOW"][0]
    with bpy.context.temp_override(window=win, area=left, region=node_region):
        bpy.ops.node.view_all()
    yield 1.0
    record(extension_enabled=bool(loaded and enabled), import_result=sorted(res),
           area_type=left.type, tree_type=space.tree_type,
           shown_tree=space.node_tree.name if space.node_tree else None,
           tree_nodes=len(tree.nodes) if tree else 0,
           custom_colored=[n.name for n in tree.nodes if n.use_custom_color] if tree else None,
           preview_faces=len(preview.data.polygons) if preview else 0,
           preview_visible=bool(preview and preview.visible_get()),
           version=bpy.app.version_string, background=bpy.app.background)
    yield {"action": "screenshot", "name": "ui_smoke.png"}


Steps(run())
