"""UI smoke test script: the full Blender UI with the extension enabled shows a
BlobTree node tree in a node editor; the harness takes the screenshot."""
import os
import sys

import addon_utils
import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from uistep import Steps, record  # noqa: E402

EXT = "bl_ext.user_default.blobtree_ink"


def largest_area(screen):
    return max(screen.areas, key=lambda a: a.width * a.height)


def run():
    yield 1.0
    yield {"action": "key", "keys": ["Escape"]}          # the splash takes the first Escape
    addon_utils.enable(EXT, default_set=True)
    loaded, enabled = addon_utils.check(EXT)
    tree = bpy.data.node_groups.new("Smoke Tree", "BlobTreeInkNodeTree")
    win = bpy.context.window_manager.windows[0]
    area = largest_area(win.screen)
    area.type = "NODE_EDITOR"
    space = area.spaces.active
    space.tree_type = "BlobTreeInkNodeTree"
    space.node_tree = tree
    yield 1.0
    record(extension_enabled=bool(loaded and enabled), area_type=area.type, tree_type=space.tree_type,
           shown_tree=space.node_tree.name if space.node_tree else None,
           version=bpy.app.version_string, background=bpy.app.background)
    yield {"action": "screenshot", "name": "ui_smoke.png"}


Steps(run())
