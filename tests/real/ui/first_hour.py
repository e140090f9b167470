"""Real-UI script: an artist's first hour (issue #28), with the user's keys and clicks
sent by xdotool wherever the UI allows. Python set-up (and why) is marked [Python].

1. Past the splash (Escape); the extension enabled [Python: the preferences' add-on list
   is not worth clicking through]; the default cube deleted: the mouse over the 3D
   viewport, Delete.
2. A BlobTree built by hand. The 3D viewport split in two and its left half made a
   BlobTree node editor with a new, empty tree [Python: area_split, the area type and
   bpy.data.node_groups.new; their header buttons have no screen position to compute].
   With the mouse over the editor: N hides its sidebar; Shift+A, the node's name typed,
   Return and a click add two Points, a Blend and a Model Output (a new tree has none).
   The links are mouse drags from socket to socket, the sockets found on a screenshot
   by their colour (the harness only moves and clicks: xdotool's mousedown, moves and
   mouseup are sent from here, between ticks). Blender's Make Links (F) links nothing
   between custom sockets (its best_socket_input only tries built-in socket types). The
   second Point's Center X: a click into the field, Ctrl+A, "1", Return. The preview
   mesh appears. N shows the sidebar again [Python: its BlobTree Ink tab].
   The camera, as an artist frames a shot: a click on the preview selects it; F3 "frame
   selected"; six wheel steps out (the camera sees about half the viewport's width); F3
   "align active camera to view"; F3 "frame camera bounds"; Alt+A deselects. The looks
   draw from the scene camera (From Camera is on by default).
3. F3, "trace feature outlines", Return; the run's end awaited.
4. F3, "stippled", Return (Object > BlobTree Ink > Looks > Stippled); the end awaited.
5. The runner's hook armed in the hatching [Python: CHUNK_LINES 5, so that the hatching
   has dozens of parts; held after 20 of them]; F3, "hatched", Return; when the worker holds
   and its parts are drawn: a screenshot, Escape, the run's end: a stopped look is one
   drawing too, the stippled look's stipples go. Then F3 "hatched" again, to its end
   (the full count). Then the style's hatching switched off [Python] and F3
   "trace feature outlines" again: the outlines alone, the hatched look not run again.
   Then hatching and stipples ticked [Python] and F3 "place strokes": both together.
6. F12 with the mouse over the 3D viewport in the scene's engine (EEVEE in factory
   settings) [Python: the resolution at 50 %, 960 x 540; the Render Result saved with
   save_render]; the engine switched to Workbench [Python] and F12 again, with the mouse
   over the render window.

Facts for the test go to facts.json; each layer's strokes projected into the camera (in
render pixels) to render_points.json; the silhouette, the stipples and the hatching
projected into the viewport (in screen pixels) to viewport_points.json."""
import json
import os
import sys
import time

import bpy
import numpy as np
from bpy_extras.object_utils import world_to_camera_view
from bpy_extras.view3d_utils import location_3d_to_region_2d
from mathutils import Vector

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from uikit import (F12, drag, drawing_of, in_viewport, menu_search, read_screen, redrawn,  # noqa: E402
                   region_of, screen_xy, until, watch_redraws, world)
from uistep import EXT, OUT, Steps, record, started  # noqa: E402

TREE = "BlobTreeInkNodeTree"
LAYERS = ("Silhouette", "Crease", "Curvature", "Stipples", "Hatching")
SOCKET_RGB = np.array([89, 191, 242])       # the field socket's colour (blobtree_nodes.sockets), on screen
ENDED = ("done", "stopped", "failed", "tree edited", "cancelled")
CENTER_X = "1"                              # the second Point's Center X, typed into its field (two
                                            # balls of radius 1 a unit apart: a peanut with a waist)
HATCH_CHUNK = 5                             # hatching map lines per part of the hatching: it has dozens of parts
HOLD_AT = ("hatching", 20)                  # the worker holds after 20 parts (a part of lines all in the
                                            # light draws nothing: part 1 could hold it with no hatching)
ZOOM_OUT = 6                                # wheel steps out before the camera takes the view
def node_point(win, region, node, dx, dy):
    """Screen pixels of a point (dx, dy) UI units right of and below a node's top left."""
    s = bpy.context.preferences.system.ui_scale
    x, y = region.view2d.view_to_region((node.location.x + dx) * s, (node.location.y - dy) * s, clip=False)
    return screen_xy(win, region, x, y)


def node_rect(win, region, node):
    """A node's screen rectangle: left, top, right, bottom."""
    s = bpy.context.preferences.system.ui_scale
    v2d = region.view2d
    x0, y0 = v2d.view_to_region(node.location.x * s, node.location.y * s, clip=False)
    x1, y1 = v2d.view_to_region(node.location.x * s + node.dimensions.x, node.location.y * s - node.dimensions.y,
                                clip=False)
    (l, t), (r, b) = screen_xy(win, region, x0, y0), screen_xy(win, region, x1, y1)
    return l, t, r, b


def sockets(px, rect, side):
    """Screen centres of the field sockets drawn on a node's left (inputs) or right
    (outputs) edge, top to bottom, found by their colour on a screenshot."""
    l, t, r, b = rect
    x = l if side == "in" else r
    x0, y0 = max(x - 7, 0), max(t, 0)
    band = px[y0:b + 1, x0:x + 8]
    ys, xs = np.nonzero(np.abs(band - SOCKET_RGB).max(axis=2) < 40)
    found, run = [], []
    for y in sorted(set(ys)):
        if run and y - run[-1] > 2:
            found.append(run)
            run = []
        run.append(y)
    if run:
        found.append(run)
    out = []
    for rows in found:
        keep = np.isin(ys, rows)
        if keep.sum() >= 6:                   # a socket's disc, not a stray pixel of a link
            out.append((int(round(x0 + xs[keep].mean())), int(round(y0 + ys[keep].mean()))))
    return out


def counts(obj):
    return {name: len(drawing_of(obj, name)) for name in LAYERS}


def run_look(ill, win, region, text, seconds):
    """A request or look through menu search, then its end; the run's figures."""
    ill.last_run.clear()
    yield from menu_search(win, region, text)
    yield from until(lambda: ill.last_run.get("state") in ENDED, seconds, f"the run of '{text}' to end")
    return dict(ill.last_run)


def run():
    # --- 1. past the splash, the extension, the default cube deleted ------------------------
    win, view3d, vregion = yield from started(keep_cube=True)       # an artist deletes it below
    watch_redraws()
    record(extension_enabled=EXT in bpy.context.preferences.addons, version=bpy.app.version_string,
           background=bpy.app.background, selected_at_start=sorted(o.name for o in bpy.context.selected_objects))
    x, y = screen_xy(win, vregion, vregion.width / 2, vregion.height / 2)
    yield {"action": "mouse", "x": x, "y": y}
    yield {"action": "key", "keys": ["Delete"], "pause": 0.5}
    yield from until(lambda: "Cube" not in bpy.data.objects, 10, "the cube to go")
    record(objects_after_delete=sorted(o.name for o in bpy.data.objects))
    yield {"action": "screenshot", "name": "first_hour_1_cube_deleted.png"}

    # --- 2. a BlobTree node editor beside the viewport, a tree built by hand ---------------
    with bpy.context.temp_override(window=win, area=view3d, region=vregion):
        bpy.ops.screen.area_split(direction="VERTICAL", factor=0.5)
    yield 0.5
    left, right = sorted((a for a in win.screen.areas if a.type == "VIEW_3D"), key=lambda a: a.x)
    left.type = "NODE_EDITOR"
    editor = left
    space = editor.spaces.active
    space.tree_type = TREE
    tree = bpy.data.node_groups.new("Blobs", TREE)
    space.node_tree = tree
    view3d, vregion = right, region_of(right, "WINDOW")
    yield from redrawn(editor)                           # its regions have their sizes once drawn
    nregion = region_of(editor, "WINDOW")
    record(nodes_in_new_tree=sorted(getattr(n, "kind", n.bl_idname) for n in tree.nodes))
    cx, cy = screen_xy(win, nregion, nregion.width / 2, nregion.height / 2)
    if space.show_region_ui:                             # the editor opens with its sidebar: N hides it
        yield {"action": "mouse", "x": cx, "y": cy}
        yield {"action": "key", "keys": ["n"], "pause": 0.5}
        yield from until(lambda: not space.show_region_ui, 5, "N to hide the node editor's sidebar")
    added = {}
    for text, kind, fx, fy in (("point", "point", 0.08, 0.86), ("point", "point", 0.08, 0.42),
                               ("blend", "blend", 0.42, 0.66), ("model output", "output", 0.70, 0.66)):
        before = set(n.name for n in tree.nodes)
        yield {"action": "mouse", "x": cx, "y": cy}
        yield {"action": "key", "keys": ["shift+a"], "pause": 0.6}
        yield {"action": "type", "text": text, "pause": 0.8}
        yield {"action": "key", "keys": ["Return"], "pause": 0.6}
        tx, ty = screen_xy(win, nregion, nregion.width * fx, nregion.height * fy)
        yield {"action": "mouse", "x": tx, "y": ty, "click": 1, "pause": 0.4}
        yield from until(lambda: len(tree.nodes) == len(before) + 1, 5, f"Shift+A '{text}' to add a node")
        new = next(n for n in tree.nodes if n.name not in before)
        added.setdefault(kind, []).append(new.name)
    record(nodes_added=[[k, n] for k, names in added.items() for n in names],
           node_kinds=sorted(getattr(n, "kind", n.bl_idname) for n in tree.nodes))
    yield from redrawn(editor)
    yield {"action": "screenshot", "name": "first_hour_2_nodes.png"}
    point_a, point_b = (tree.nodes[n] for n in added["point"])
    blend, output = tree.nodes[added["blend"][0]], tree.nodes[added["output"][0]]
    # the links, dragged from socket to socket
    for src, dst, k in ((point_a, blend, 0), (point_b, blend, 1), (blend, output, 0)):
        shot = f"links_{len(tree.links)}.png"
        yield from redrawn(editor)                       # the sockets a link added are on screen
        yield {"action": "screenshot", "name": shot}
        px = read_screen(shot)
        outs = sockets(px, node_rect(win, nregion, src), "out")
        ins = sockets(px, node_rect(win, nregion, dst), "in")
        record(**{f"sockets_{src.name}_{dst.name}": [outs, ins]})
        n0 = len(tree.links)
        yield from drag(outs[0], ins[k])
        yield from until(lambda: len(tree.links) == n0 + 1, 5, f"a link from {src.name} to {dst.name}")
    links = sorted([l.from_node.name, l.from_socket.name, l.to_node.name, l.to_socket.name] for l in tree.links)
    record(links=links)
    # the second Point's Center X: a click into the field, the value typed, Return
    x, y = node_point(win, nregion, point_b, 95, 98)
    yield {"action": "mouse", "x": x, "y": y, "click": 1, "pause": 0.5}
    yield {"action": "screenshot", "name": "center_field_editing.png"}
    yield {"action": "key", "keys": ["ctrl+a"], "pause": 0.3}
    yield {"action": "type", "text": CENTER_X, "pause": 0.3}
    yield {"action": "key", "keys": ["Return"], "pause": 0.5}
    yield from until(lambda: abs(point_b.center[0] - float(CENTER_X)) < 1e-6, 5, "the typed Center X")
    # the preview follows the typed centre: the second ball's side reaches x = 1 + 0.45
    reach = float(CENTER_X) + 0.3

    def preview_reaches():
        obj = tree.preview_object
        return obj is not None and len(obj.data.polygons) > 0 and max(c[0] for c in obj.bound_box) > reach
    yield from until(preview_reaches, 20, "the preview mesh of the edited tree")
    preview = tree.preview_object
    record(centers=[[round(v, 4) for v in n.center] for n in (point_a, point_b)],
           radii=[n.radius for n in (point_a, point_b)], preview_faces=len(preview.data.polygons),
           preview_x=[round(min(c[0] for c in preview.bound_box), 3), round(max(c[0] for c in preview.bound_box), 3)],
           node_errors=[n.error for n in tree.nodes], preview_name=preview.name)
    yield from redrawn(editor)
    yield {"action": "screenshot", "name": "first_hour_2_tree.png"}
    # the sidebar's BlobTree Ink tab in the node editor (N; the tab is set by Python): its
    # layers and their counts in the screenshots that follow
    yield {"action": "mouse", "x": cx, "y": cy}
    yield {"action": "key", "keys": ["n"], "pause": 0.5}
    yield from until(lambda: space.show_region_ui, 5, "N to show the node editor's sidebar")
    yield 0.5
    region_of(editor, "UI").active_panel_category = "BlobTree Ink"
    yield 0.5

    # --- the camera: select the preview, frame it, align the camera to the view ----------
    rv3d = view3d.spaces.active.region_3d
    centre = preview.matrix_world @ (sum((Vector(c) for c in preview.bound_box), Vector()) / 8)
    p = location_3d_to_region_2d(vregion, rv3d, centre)
    x, y = screen_xy(win, vregion, p.x, p.y)
    yield {"action": "mouse", "x": x, "y": y, "click": 1, "pause": 0.5}
    yield from until(lambda: preview.select_get(), 5, "a click to select the preview")
    yield from menu_search(win, vregion, "frame selected")
    yield from until(lambda: (rv3d.view_location - centre).length < 1e-3, 5, "Frame Selected")
    # the camera sees about half the viewport's width: the wheel zooms out first
    d0 = rv3d.view_distance
    x, y = screen_xy(win, vregion, vregion.width / 2, vregion.height / 2)
    for _ in range(ZOOM_OUT):
        yield {"action": "mouse", "x": x, "y": y, "click": 5, "pause": 0.1}
    yield from until(lambda: rv3d.view_distance > 2 * d0, 5, "the wheel to zoom out")
    cam = bpy.context.scene.camera
    cam0 = cam.matrix_world.copy()
    yield from menu_search(win, vregion, "align active camera to view")
    yield from until(lambda: cam.matrix_world != cam0 and rv3d.view_perspective == "CAMERA", 5,
                     "Align Active Camera to View")
    zoom0 = rv3d.view_camera_zoom
    yield from menu_search(win, vregion, "frame camera bounds")
    yield from until(lambda: rv3d.view_camera_zoom != zoom0, 5, "Frame Camera Bounds")
    yield {"action": "key", "keys": ["alt+a"], "pause": 0.5}          # deselect all
    yield from until(lambda: not bpy.context.selected_objects, 5, "Alt+A to deselect all")
    yield from redrawn(view3d)
    sc = bpy.context.scene
    uv = [world_to_camera_view(sc, cam, preview.matrix_world @ Vector(c)) for c in preview.bound_box]
    yield {"action": "screenshot", "name": "first_hour_2_camera.png"}
    record(model_in_camera=[[round(min(u[i] for u in uv), 3), round(max(u[i] for u in uv), 3)] for i in (0, 1)],
           view_distance=[d0, rv3d.view_distance])
    record(camera_location=list(cam.location), camera_rotation=list(cam.rotation_euler),
           view_perspective=rv3d.view_perspective)

    # --- 3. outlines --------------------------------------------------------------------
    ill = sys.modules[EXT + ".operators.illustrate"]
    runs = {}
    runs["outlines"] = yield from run_look(ill, win, vregion, "trace feature outlines", 240)
    ink = bpy.data.objects.get(f"{tree.name} Ink")
    yield from redrawn(view3d)
    overlay = view3d.spaces.active.overlay
    record(ink_name=ink.name if ink else None, ink_parent=ink.parent.name if ink and ink.parent else None,
           counts_outlines=counts(ink), paper_viewport=[view3d.spaces.active.shading.background_type,
                                                        overlay.show_floor, overlay.show_axis_x, overlay.show_axis_y])
    yield {"action": "screenshot", "name": "first_hour_3_outlines.png"}
    outlines3 = {k: drawing_of(ink, k) for k in ("Silhouette", "Crease", "Curvature")}
    on_screen = {"silhouette": in_viewport(win, vregion, rv3d, ink, outlines3["Silhouette"])}

    # --- 4. the stippled look --------------------------------------------------------------
    runs["stippled"] = yield from run_look(ill, win, vregion, "stippled", 240)
    yield from redrawn(view3d)
    record(counts_stippled=counts(ink))
    yield {"action": "screenshot", "name": "first_hour_4_stippled.png"}
    after4 = {k: drawing_of(ink, k) for k in ("Silhouette", "Crease", "Curvature", "Stipples")}
    # where the viewport shows the stipples (screen pixels)
    on_screen["stipples"] = in_viewport(win, vregion, rv3d, ink, after4["Stipples"])
    on_screen["viewport"] = [win.x + vregion.x, win.y + win.height - vregion.y - vregion.height,
                             vregion.width, vregion.height]
    record(viewport_stipples=len(on_screen["stipples"]))

    # --- 5. the hatched look, held in the middle of its hatching, stopped by Esc --------------
    sys.modules[EXT + ".pipeline.layers"].CHUNK_LINES = HATCH_CHUNK
    hold = sys.modules[EXT + ".pipeline.runner"].HOLD
    hold.arm(at=HOLD_AT)
    ill.last_run.clear()
    yield from menu_search(win, vregion, "hatched")
    yield from until(hold.reached.is_set, 240, f"the worker to hold at {HOLD_AT}")
    yield from until(lambda: len(drawing_of(ink, "Hatching")) > 0, 10, "the held part of the hatching drawn")
    yield from redrawn(view3d)
    held = dict(ill.last_run)
    record(counts_held=counts(ink), held_state=held.get("state"), held_stage=held.get("stage"))
    yield {"action": "screenshot", "name": "first_hour_5_hatching_held.png"}
    yield {"action": "key", "keys": ["Escape"], "pause": 0.5}
    yield from until(lambda: ill.last_run.get("state") in ENDED, 60, "Esc to end the run")
    runs["hatched_esc"] = dict(ill.last_run)
    hold.release()
    yield from redrawn(view3d)
    after5 = {k: drawing_of(ink, k) for k in ("Silhouette", "Crease", "Curvature", "Stipples")}
    same = {k: len(after4[k]) == len(after5[k]) and all(np.array_equal(a, b) for a, b in zip(after4[k], after5[k]))
            for k in after4}
    same_outlines_3_4 = {k: len(outlines3[k]) == len(after4[k]) and
                         all(np.array_equal(a, b) for a, b in zip(outlines3[k], after4[k])) for k in outlines3}
    record(counts_after_esc=counts(ink), same_after_esc=same, same_outlines_after_stippled=same_outlines_3_4,
           esc_warnings=runs["hatched_esc"].get("warnings"))
    yield {"action": "screenshot", "name": "first_hour_5_hatching_stopped.png"}
    # the same look to its end: the full hatching
    runs["hatched_full"] = yield from run_look(ill, win, vregion, "hatched", 240)
    yield from redrawn(view3d)
    after_full = {k: drawing_of(ink, k) for k in ("Silhouette", "Crease", "Curvature", "Stipples")}
    record(counts_full=counts(ink), full_warnings=ill.last_run.get("warnings"),
           same_after_full={k: len(after4[k]) == len(after_full[k]) and
                            all(np.array_equal(a, b) for a, b in zip(after4[k], after_full[k])) for k in after4})
    yield {"action": "screenshot", "name": "first_hour_5_hatched_full.png"}
    on_screen["hatching"] = in_viewport(win, vregion, rv3d, ink, drawing_of(ink, "Hatching"))
    with open(os.path.join(OUT, "viewport_points.json"), "w") as fh:
        json.dump(on_screen, fh)
    # a request after a look is that request: the look is not run again (Blender gives an
    # operator property a menu item leaves unset the last call's value unless SKIP_SAVE)
    tree.ink.hatching = False                                      # [Python] a change the look would undo
    runs["outlines_after_look"] = yield from run_look(ill, win, vregion, "trace feature outlines", 240)
    record(hatching_after_request=tree.ink.hatching, counts_after_request=counts(ink))
    tree.ink.hatching = tree.ink.stipples = True                   # [Python] both, for one request
    runs["place_strokes"] = yield from run_look(ill, win, vregion, "place strokes", 240)
    record(counts_placed=counts(ink))
    record(runs={k: {f: v.get(f) for f in ("state", "strokes", "stage", "fraction", "iterations")}
                 for k, v in runs.items()})

    # --- 6. F12: the scene's engine, then Workbench -------------------------------------------
    sc = bpy.context.scene
    sc.render.resolution_percentage = 50                 # 960 x 540: a quicker render than 1920 x 1080
    done = []
    bpy.app.handlers.render_complete.append(lambda *a: done.append("complete"))
    bpy.app.handlers.render_cancel.append(lambda *a: done.append("cancel"))
    w = sc.render.resolution_x * sc.render.resolution_percentage // 100
    h = sc.render.resolution_y * sc.render.resolution_percentage // 100
    layers = {name: drawing_of(ink, name) for name in LAYERS}
    points = {}
    for name, strokes in layers.items():
        out = []
        for s in strokes:
            uv = [world_to_camera_view(sc, sc.camera, Vector(q)) for q in world(ink, s)]
            out.append([[round(u.x * w, 2), round((1 - u.y) * h, 2)] for u in uv])
        points[name] = out
    verts = np.empty(3 * len(preview.data.vertices), np.float32)
    preview.data.vertices.foreach_get("co", verts)
    uv = [world_to_camera_view(sc, sc.camera, Vector(q)) for q in world(preview, verts.reshape(-1, 3).astype(float))]
    points["preview_vertices"] = [[round(u.x * w, 2), round((1 - u.y) * h, 2)] for u in uv]
    with open(os.path.join(OUT, "render_points.json"), "w") as fh:
        json.dump(points, fh)
    renders = {}
    mouse = screen_xy(win, vregion, vregion.width / 2, vregion.height / 2)
    for label in ("scene", "workbench"):
        if label == "workbench":
            sc.render.engine = "BLENDER_WORKBENCH"
        engine = sc.render.engine
        done.clear()
        t0 = time.monotonic()
        yield {"action": "mouse", "x": mouse[0], "y": mouse[1]}
        yield {"action": "key", "keys": [F12], "pause": 1.0}
        yield from until(lambda: done and not bpy.app.is_job_running("RENDER"), 300, f"the {engine} render")
        seconds = time.monotonic() - t0
        yield 1.0
        path = os.path.join(OUT, f"render_{label}.png")
        bpy.data.images["Render Result"].save_render(path)
        img = bpy.data.images.load(path, check_existing=False)
        renders[label] = {"engine": engine, "size": list(img.size), "end": done[0], "seconds": round(seconds, 1)}
        bpy.data.images.remove(img)
        wins = [[v.x, v.y, v.width, v.height] for v in bpy.context.window_manager.windows]
        renders[label]["windows"] = wins
        yield {"action": "screenshot", "name": f"first_hour_6_render_{label}.png"}
        if len(bpy.context.window_manager.windows) > 1:   # F12 again with the mouse over the render window
            rw = bpy.context.window_manager.windows[-1]
            mouse = (rw.x + rw.width // 2, win.height - rw.y - rw.height // 2)
    record(renders=renders, render_size=[w, h], scene_engine=renders["scene"]["engine"],
           view_transform=sc.view_settings.view_transform, world=sc.world.name if sc.world else None,
           preview_hide_render=preview.hide_render)


Steps(run())
