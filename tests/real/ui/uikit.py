"""Helpers of the real-UI scripts: screen pixels of regions, waiting on conditions and
on redraws, menu search, mouse drags, screenshots read back, and the strokes of an
ink object's layers projected into the viewport."""
import os
import subprocess
import time

import bpy
import numpy as np
from bpy_extras.view3d_utils import location_3d_to_region_2d
from mathutils import Vector

from uistep import OUT

# xdotool sends the keysyms F3 and F12 with Alt held under Xvfb (its keymap has them on
# a CTRL+ALT key type, and xdotool picks a level that needs Alt): Alt+F3 is not menu
# search. An explicit keycode (xdotool takes a number as one) sends the bare key.
F3, F12 = "69", "96"


class Timeout(AssertionError):
    pass


draws = {"VIEW_3D": 0, "NODE_EDITOR": 0}      # draws of each editor's main region so far


def _drawn(kind):
    draws[kind] += 1


def watch_redraws():
    """Count the draws of the 3D viewports' and node editors' main regions (:func:`redrawn`)."""
    bpy.types.SpaceView3D.draw_handler_add(_drawn, ("VIEW_3D",), "WINDOW", "POST_PIXEL")
    bpy.types.SpaceNodeEditor.draw_handler_add(_drawn, ("NODE_EDITOR",), "WINDOW", "POST_PIXEL")


def until(cond, seconds, what):
    """Poll ``cond`` until it holds; a screenshot and Timeout naming ``what`` if it does not."""
    end = time.monotonic() + seconds
    while not cond():
        if time.monotonic() > end:
            yield {"action": "screenshot", "name": "timeout.png"}
            raise Timeout(f"waited {seconds} s for {what}")
        yield 0.1


def redrawn(area):
    """Until the editor has drawn again (tagged for a redraw now): a screenshot then shows
    what the data holds."""
    kind, n = area.type, draws[area.type]
    area.tag_redraw()
    yield from until(lambda: draws[kind] > n, 10, f"the {kind} to redraw")


def region_of(area, kind):
    return next(r for r in area.regions if r.type == kind)


def screen_xy(win, region, x, y):
    """X screen pixels of a point in a region (Blender counts from the window's bottom)."""
    return int(round(win.x + region.x + x)), int(round(win.y + win.height - (region.y + y)))


def read_screen(name):
    """A screenshot's RGB pixels (0..255, rows from the top), read by Blender's loader."""
    img = bpy.data.images.load(os.path.join(OUT, name), check_existing=False)
    try:
        w, h = img.size
        px = np.empty(w * h * img.channels, np.float32)
        img.pixels.foreach_get(px)
        return np.round(255 * px.reshape(h, w, img.channels)[::-1, :, :3])
    finally:
        bpy.data.images.remove(img)


def xdotool(*args):
    subprocess.run(["xdotool", *map(str, args)], check=True)


def drag(a, b):
    """Press the left button at ``a``, move to ``b`` in a few steps, release: a mouse drag
    (the harness's actions move and click only; xdotool runs here, between ticks, so
    that Blender sees each event)."""
    xdotool("mousemove", *a)
    yield 0.3
    xdotool("mousedown", 1)
    yield 0.3
    for t in (0.05, 0.2, 0.5, 0.8, 1.0):
        xdotool("mousemove", round(a[0] + t * (b[0] - a[0])), round(a[1] + t * (b[1] - a[1])))
        yield 0.15
    yield 0.3
    xdotool("mouseup", 1)
    yield 0.5


def menu_search(win, region, text):
    """F3 with the mouse over a region, the text typed, Return: the first item found."""
    x, y = screen_xy(win, region, region.width / 2, region.height / 2)
    yield {"action": "mouse", "x": x, "y": y}
    yield {"action": "key", "keys": [F3], "pause": 0.8}
    yield {"action": "type", "text": text, "pause": 1.0}
    yield {"action": "screenshot", "name": f"menu_search_{text.replace(' ', '_')}.png"}
    yield {"action": "key", "keys": ["Return"], "pause": 0.5}


def drawing_of(obj, layer_name, frame=None):
    """A layer's strokes as arrays of points (object space): its first drawing, or the
    one keyed at ``frame``."""
    layer = obj.data.layers.get(layer_name) if obj is not None else None
    if layer is None or not len(layer.frames):
        return []
    keyed = [f for f in layer.frames if frame is None or f.frame_number == frame]
    if not keyed:
        return []
    d = keyed[0].drawing
    n = len(d.strokes)
    if not n:
        return []
    off = np.empty(n + 1, np.int32)
    d.curve_offsets.foreach_get("value", off)
    pos = np.empty(3 * int(off[-1]), np.float32)
    d.attributes["position"].data.foreach_get("vector", pos)
    pos = pos.reshape(-1, 3).astype(float)
    return [pos[off[i]:off[i + 1]] for i in range(n)]


def world(obj, pts):
    m = np.array(obj.matrix_world)
    return pts @ m[:3, :3].T + m[:3, 3]


def in_viewport(win, region, rv3d, obj, strokes):
    """Screen pixels where the viewport shows the strokes' points (those inside it)."""
    pts = np.concatenate(strokes) if strokes else np.zeros((0, 3))
    out = []
    for q in world(obj, pts):
        p = location_3d_to_region_2d(region, rv3d, Vector(q))
        if p is not None and 2 <= p.x < region.width - 2 and 2 <= p.y < region.height - 2:
            out.append(screen_xy(win, region, p.x, p.y))
    return out
