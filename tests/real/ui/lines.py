"""Real-UI script: an artist turns on curvature-sign lines, suggestive contours and
apparent ridges in the sidebar and traces them, with the clicks and keys sent by
xdotool. Python set-up (and why) is marked [Python].

1. Past the splash (Escape); the extension enabled, the default cube deleted and the
   heart imported with its preview [Python: the file browser is not what this test is
   about]; nothing selected.
   The view framed on the heart: the preview selected [Python], F3 "frame selected",
   Alt+A.
2. The mouse over the 3D viewport, N shows the sidebar [Python: its BlobTree Ink tab].
   A screenshot; the Lines toggles are found on it: two a row, the first row of the
   sidebar that is mostly the selected-toggle blue (Silhouette and Crease are on),
   Curvature the grey toggle below Silhouette. A click on Curvature, then one on
   Suggestive (right of it); a screenshot, and a click on Ridges (below Curvature, now
   blue).
3. F3, "trace feature outlines", Return; the run's end awaited; a screenshot.

Facts go to facts.json; the Curvature, Suggestive and Ridges layers' points projected into the
viewport (screen pixels) to lines_points.json."""
import json
import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from uikit import (drawing_of, in_viewport, menu_search, read_screen, redrawn, region_of, screen_xy,  # noqa: E402
                   until, watch_redraws)
from uistep import EXT, OUT, Steps, record, start_with_example  # noqa: E402

ENDED = ("done", "stopped", "failed", "tree edited", "cancelled")
TOGGLE_ON = np.array([71, 114, 179])        # the default theme's selected toggle (inner_sel), on screen


def blue(px, y, x0, x1):
    return np.abs(px[y, x0:x1] - TOGGLE_ON).max(axis=-1) < 30


def lines_row(px, left, top, width, height):
    """Screen (x0, x1, y) of the first sidebar row mostly in the selected-toggle blue:
    the Lines toggles' first row, Silhouette and Crease on (x0..x1; y its top)."""
    for y in range(top, top + height):
        on = np.flatnonzero(blue(px, y, left, left + width))
        if len(on) > 0.5 * width:
            return left + int(on.min()), left + int(on.max()), y
    return None


def below(px, x, y):
    """The first screen row under the blue toggle at (x, y) that is not blue: the
    toggle's bottom edge."""
    while blue(px, y, x, x + 1).all():
        y += 1
    return y


def lines(tree):
    return [k for k in ("silhouette", "crease", "curvature", "suggestive", "ridges") if getattr(tree.ink, f"line_{k}")]


def run():
    win, view3d, vregion = yield from start_with_example("heart", preview=True)
    watch_redraws()
    rv3d = view3d.spaces.active.region_3d
    tree = bpy.data.node_groups["heart"]
    yield from until(lambda: tree.preview_object is not None, 20, "the preview")
    bpy.ops.ed.undo_push(message="set up")
    # the view framed on the heart, as an artist does before drawing: the preview selected
    # [Python: a click would have to find it], F3 "frame selected", Alt+A deselects
    for obj in bpy.context.selected_objects:
        obj.select_set(False)
    tree.preview_object.select_set(True)
    d0 = rv3d.view_distance
    yield from menu_search(win, vregion, "frame selected")
    yield from until(lambda: rv3d.view_distance < 0.8 * d0, 5, "Frame Selected")
    yield {"action": "key", "keys": ["alt+a"], "pause": 0.5}
    yield from until(lambda: not bpy.context.selected_objects, 5, "Alt+A to deselect all")

    # --- 2. the sidebar, its Lines row, a click on Curvature ------------------------------------
    space = view3d.spaces.active
    x, y = screen_xy(win, vregion, vregion.width / 2, vregion.height / 2)
    yield {"action": "mouse", "x": x, "y": y}
    if not space.show_region_ui:
        yield {"action": "key", "keys": ["n"], "pause": 0.5}
        yield from until(lambda: space.show_region_ui, 5, "N to show the sidebar")
    ui = region_of(view3d, "UI")
    ui.active_panel_category = "BlobTree Ink"
    yield from redrawn(view3d)
    yield 0.5
    yield {"action": "screenshot", "name": "lines_1_sidebar.png"}
    record(lines_before=lines(tree))
    px = read_screen("lines_1_sidebar.png")
    left, top = screen_xy(win, ui, 0, ui.height)
    row = lines_row(px, left, top, ui.width, ui.height)
    record(lines_row=row)
    if row is None:
        raise AssertionError("no Lines row with its toggles on in the sidebar")
    x0, x1, y = row
    cx = x0 + (x1 - x0) // 4                              # the middle of the left column: Silhouette
    cy = below(px, cx, y) + 8                             # ... and, in the row below it, Curvature
    record(curvature_click=(cx, cy))
    yield {"action": "mouse", "x": cx, "y": cy, "click": 1, "pause": 0.5}
    yield from until(lambda: tree.ink.line_curvature, 5, "a click on the Curvature toggle")
    record(lines_after=lines(tree))
    yield {"action": "mouse", "x": cx + (x1 - x0) // 2, "y": cy, "click": 1, "pause": 0.5}
    yield from until(lambda: tree.ink.line_suggestive, 5, "a click on the Suggestive toggle")
    yield {"action": "mouse", "x": x, "y": y, "pause": 0.5}     # away: Suggestive's tooltip would hide Ridges
    yield from redrawn(view3d)
    yield {"action": "screenshot", "name": "lines_2_curvature_on.png"}
    record(lines_two=lines(tree))
    # under Curvature: Ridges (Curvature's blue found near the toggle's left end, clear of
    # its label, from the click on, then its bottom edge)
    px = read_screen("lines_2_curvature_on.png")
    top = cy
    while not blue(px, top, x0 + 6, x0 + 7).all() and top < cy + 30:
        top += 1
    cy = below(px, x0 + 6, top) + 8
    record(ridges_click=(cx, cy))
    yield {"action": "mouse", "x": cx, "y": cy, "click": 1, "pause": 0.5}
    yield from until(lambda: tree.ink.line_ridges, 5, "a click on the Ridges toggle")
    yield from redrawn(view3d)
    record(lines_last=lines(tree))

    # --- 3. trace ---------------------------------------------------------------------------------
    ill = sys.modules[EXT + ".operators.illustrate"]
    ill.last_run.clear()
    yield from menu_search(win, vregion, "trace feature outlines")
    yield from until(lambda: ill.last_run.get("state") in ENDED, 240, "the trace to end")
    ink = bpy.data.objects[f"{tree.name} Ink"]
    record(state=ill.last_run.get("state"),
           counts={k: len(drawing_of(ink, k)) for k in ("Silhouette", "Crease", "Curvature", "Suggestive", "Ridges")})
    yield from redrawn(view3d)
    yield {"action": "screenshot", "name": "lines_3_traced.png"}
    with open(os.path.join(OUT, "lines_points.json"), "w") as fh:
        json.dump({k.lower(): in_viewport(win, vregion, rv3d, ink, drawing_of(ink, k))
                   for k in ("Curvature", "Suggestive", "Ridges")}, fh)


Steps(run())
