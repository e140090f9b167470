"""Real-UI script: an artist bakes an animation, with keys sent by xdotool. Python
set-up (and why) is marked [Python].

1. Past the splash (Escape); the extension enabled and two blobs imported with their
   preview, the second following an Empty keyed from x = 0 (frame 1) to x = 2 (frame 6),
   a camera on both, the scene's range 1-6, the grid 10 [Python: building an animation
   by hand is not what this test is about].
2. The runner's hook armed for the third worker started, frame 3's [Python]. The mouse
   over the viewport, F3, "bake frames", Return (Object > BlobTree Ink > Bake Frames:
   the tree's bake range, the scene's). When frame 3's worker holds: a screenshot,
   Escape. The bake stops with frames 1 and 2 kept; the timeline is back on frame 1.
   Frames 4-6 [Python: the range], held in frame 5, and Ctrl+Z: the bake stops as with
   Escape (the model stays, frame 4 kept); Ctrl+Z again takes that bake back.
3. F3 "bake frames" again: all six frames; Adjust Last Operation holds the range baked.
4. Ctrl+Z: the second bake is undone as one step (frames 1 and 2 again); Ctrl+Shift+Z
   redoes it. The bake run as Adjust Last Operation runs it (its execute, in the UI, with
   the last operation's values) bakes that range again [Python].
5. Alt+A (the preview's selection outline would lie over the silhouettes); Right arrow
   five times (the next frame each time), a screenshot at frames 1 and 6: the viewport
   shows each frame's own drawing.
6. F3 "clear frames": no frame drawn.
7. The Empty deleted in the viewport (X, Return), F3 "bake frames": the bake fails on its
   first frame (the Empty is named) and draws nothing.

Facts go to facts.json; frame 6's silhouette projected into the viewport (screen
pixels) to bake_points.json."""
import json
import os
import sys

import bpy
from mathutils import Vector

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from uikit import (F12, drawing_of, in_viewport, menu_search, redrawn, screen_xy, until,  # noqa: E402
                   watch_redraws)
from uistep import EXT, OUT, REPO, Steps, record, started  # noqa: E402

ENDED = ("done", "stopped", "failed")


def drawn(tree):
    return sorted(sys.modules[EXT + ".operators.frames"].drawn_frames(tree))


def setup(win, view3d, vregion):
    """[Python] two blobs, the second following a keyed Empty; a camera on both."""
    with bpy.context.temp_override(window=win, area=view3d, region=vregion):
        bpy.ops.blobtree_ink.import_json(filepath=os.path.join(REPO, "examples", "two_spheres.json"), preview=True)
    tree = bpy.data.node_groups["two_spheres"]
    tree.ink.grid_resolution = 10
    second = [n for n in tree.nodes if getattr(n, "kind", "") == "point"][1]
    sc = bpy.context.scene
    empty = bpy.data.objects.new("Driver", None)
    sc.collection.objects.link(empty)
    second.center_object = empty
    for frame, x in ((1, 0.0), (6, 2.0)):
        empty.location = (x, 0.0, 0.0)
        empty.keyframe_insert("location", frame=frame)
    cam = sc.camera
    cam.location = (1.0, -7.5, 1.0)
    cam.rotation_euler = (Vector((1.0, 0.0, 0.0)) - cam.location).to_track_quat("-Z", "Y").to_euler()
    sc.frame_start, sc.frame_end = 1, 6
    sc.frame_set(1)
    return tree


def run():
    win, view3d, vregion = yield from started()
    watch_redraws()
    rv3d = view3d.spaces.active.region_3d
    tree = setup(win, view3d, vregion)
    bpy.ops.ed.undo_push(message="set up")
    yield from until(lambda: tree.preview_object is not None, 20, "the preview")
    yield 1.0                                            # the import has framed the view by now
    rv3d.view_perspective = "CAMERA"                     # [Python] through the camera, as for a shot
    bake = sys.modules[EXT + ".operators.bake"]
    hold = sys.modules[EXT + ".pipeline.runner"].HOLD
    sc = bpy.context.scene

    # --- 2. Bake Frames from menu search, held in frame 3, stopped by Escape ---------------
    hold.arm(1, run=3)
    bake.last_bake.clear()
    yield from menu_search(win, vregion, "bake frames")
    yield from until(hold.reached.is_set, 240, "frame 3's worker to hold")
    yield from redrawn(view3d)
    record(held_frames=drawn(tree), held_state=bake.last_bake.get("state"), frame_while_baking=sc.frame_current)
    yield {"action": "screenshot", "name": "bake_held.png"}
    yield {"action": "key", "keys": ["Escape"], "pause": 0.5}
    yield from until(lambda: bake.last_bake.get("state") in ENDED, 60, "Escape to stop the bake")
    hold.release()
    record(stopped_state=bake.last_bake["state"], stopped_frames=drawn(tree), frame_after_stop=sc.frame_current)
    yield from redrawn(view3d)
    yield {"action": "screenshot", "name": "bake_stopped.png"}

    # --- 2b. Ctrl+Z while a bake runs stops it as Escape does; Ctrl+Z again takes it back -----
    tree.ink.use_scene_range = False                     # [Python] a range of its own, 4-6, this once
    tree.ink.frame_start, tree.ink.frame_end = 4, 6
    bpy.ops.ed.undo_push(message="a range of its own")
    hold.arm(1, run=2)
    bake.last_bake.clear()
    yield from menu_search(win, vregion, "bake frames")
    yield from until(hold.reached.is_set, 240, "frame 5's worker to hold")
    x, y = screen_xy(win, vregion, vregion.width / 2, vregion.height / 2)
    yield {"action": "mouse", "x": x, "y": y}
    yield {"action": "key", "keys": ["ctrl+z"], "pause": 0.5}
    yield from until(lambda: bake.last_bake.get("state") in ENDED, 60, "Ctrl+Z to stop the bake")
    hold.release()
    record(undo_key_state=bake.last_bake["state"], undo_key_frames=drawn(tree),
           tree_after_undo_key="two_spheres" in bpy.data.node_groups)
    yield {"action": "key", "keys": ["ctrl+z"], "pause": 1.0}
    tree, sc = bpy.data.node_groups["two_spheres"], bpy.context.scene      # undo replaced the data
    record(frames_after_undoing_the_stopped_bake=drawn(tree))
    tree.ink.use_scene_range = True                      # [Python] the scene's range again
    bpy.ops.ed.undo_push(message="the scene's range")

    # --- 3. the whole range -----------------------------------------------------------------
    bake.last_bake.clear()
    yield from menu_search(win, vregion, "bake frames")
    yield from until(lambda: bake.last_bake.get("state") in ENDED, 300, "the bake of frames 1-6")
    ink = bpy.data.objects[f"{tree.name} Ink"]
    right = {f: max((float((ink.matrix_world @ Vector(p)).x) for s in drawing_of(ink, "Silhouette", f) for p in s),
                    default=None) for f in range(1, 7)}
    last = bpy.context.window_manager.operators[-1]      # what Adjust Last Operation shows
    redo = {k: getattr(last.properties, k) for k in ("tree_name", "frame_start", "frame_end")}
    record(full_state=bake.last_bake["state"], full_frames=drawn(tree), silhouette_right=right,
           last_operator=last.bl_idname, last_range=[redo["frame_start"], redo["frame_end"]])

    # --- 4. undo: the second bake goes as one step; redo brings it back -----------------------
    x, y = screen_xy(win, vregion, vregion.width / 2, vregion.height / 2)
    yield {"action": "mouse", "x": x, "y": y}
    yield {"action": "key", "keys": ["ctrl+z"], "pause": 1.0}
    yield from until(lambda: drawn(bpy.data.node_groups["two_spheres"]) != list(range(1, 7)), 10, "Ctrl+Z")
    record(frames_after_undo=drawn(bpy.data.node_groups["two_spheres"]))
    yield {"action": "key", "keys": ["ctrl+shift+z"], "pause": 1.0}
    yield from until(lambda: drawn(bpy.data.node_groups["two_spheres"]) == list(range(1, 7)), 10, "Ctrl+Shift+Z")
    tree = bpy.data.node_groups["two_spheres"]
    ink = bpy.data.objects[f"{tree.name} Ink"]
    sc = bpy.context.scene
    record(frames_after_redo=drawn(tree))
    # [Python] what a change in Adjust Last Operation runs: the bake's execute, in the UI,
    # with the panel's values (run from a script it makes no undo step, so it comes after
    # the undo and redo above)
    bake.last_bake.clear()
    with bpy.context.temp_override(window=win, area=view3d, region=vregion):
        bpy.ops.blobtree_ink.bake("EXEC_DEFAULT", **redo)    # the values the panel showed (before the undo)
    tree = bpy.data.node_groups["two_spheres"]
    ink = bpy.data.objects[f"{tree.name} Ink"]
    sc = bpy.context.scene
    record(redone_state=bake.last_bake.get("state"), redone_frames=drawn(tree))

    # --- 5. the timeline, a frame at a time (nothing selected: the preview's selection
    # outline would lie over the silhouettes) --------------------------------------------------
    yield {"action": "key", "keys": ["alt+a"], "pause": 0.5}
    yield from until(lambda: not bpy.context.selected_objects, 5, "Alt+A to deselect all")
    frames_seen = [sc.frame_current]
    yield from redrawn(view3d)
    yield {"action": "screenshot", "name": "bake_frame_1.png"}
    for _ in range(5):
        n = sc.frame_current
        yield {"action": "key", "keys": ["Right"], "pause": 0.3}
        yield from until(lambda: sc.frame_current == n + 1, 5, "Right arrow to step a frame")
        frames_seen.append(sc.frame_current)
    yield from until(lambda: tree.preview_object is not None and
                     max(c[0] for c in tree.preview_object.bound_box) > 2.2, 20, "the preview at frame 6")
    yield from redrawn(view3d)
    yield {"action": "screenshot", "name": "bake_frame_6.png"}
    points = {"frame6": in_viewport(win, vregion, rv3d, ink, drawing_of(ink, "Silhouette", 6)),
              "frame1": in_viewport(win, vregion, rv3d, ink, drawing_of(ink, "Silhouette", 1))}
    with open(os.path.join(OUT, "bake_points.json"), "w") as fh:
        json.dump(points, fh)
    record(frames_seen=frames_seen)

    # --- 6. Clear Frames ------------------------------------------------------------------------
    tree = bpy.data.node_groups["two_spheres"]
    yield from menu_search(win, vregion, "clear frames")
    yield from until(lambda: not drawn(tree), 10, "Clear Frames")
    record(frames_after_clear=drawn(tree))

    # --- 6b. a render draws a frame; Clear Frames, then Ctrl+Z brings that frame back -----------
    render = sys.modules[EXT + ".operators.render_frames"]
    sc.frame_set(2)
    sc.render.resolution_percentage = 25                 # [Python] a small render, as for a test shot
    n = len(render.drawn)
    yield {"action": "mouse", "x": x, "y": y}
    yield {"action": "key", "keys": [F12], "pause": 1.0}
    yield from until(lambda: len(render.drawn) > n and not bpy.app.is_job_running("RENDER"), 120, "the F12 render")
    yield 2.0
    rendered = drawn(tree)
    rw = bpy.context.window_manager.windows[-1]
    yield {"action": "mouse", "x": rw.x + rw.width // 2, "y": win.height - rw.y - rw.height // 2}
    yield {"action": "key", "keys": ["Escape"], "pause": 1.0}    # the render window closes
    yield from until(lambda: len(bpy.context.window_manager.windows) == 1, 10, "Escape to close the render")
    yield from menu_search(win, vregion, "clear frames")
    yield from until(lambda: not drawn(bpy.data.node_groups["two_spheres"]), 10, "Clear Frames after the render")
    cleared = drawn(bpy.data.node_groups["two_spheres"])
    yield {"action": "mouse", "x": x, "y": y}
    yield {"action": "key", "keys": ["ctrl+z"], "pause": 1.0}
    yield from until(lambda: drawn(bpy.data.node_groups["two_spheres"]), 10, "Ctrl+Z after Clear Frames")
    tree = bpy.data.node_groups["two_spheres"]
    sc = bpy.context.scene
    record(frames_rendered=rendered, frames_cleared_after_render=cleared, frames_after_undoing_the_clear=drawn(tree))

    # --- 7. the driving Empty deleted in the viewport (clicked, X, Return), then a bake ------------
    driver = bpy.data.objects["Driver"]
    with bpy.context.temp_override(window=win, area=view3d, region=vregion):
        bpy.ops.object.select_all(action="DESELECT")
    driver.select_set(True)                              # [Python] an Empty is hard to click
    bpy.context.view_layer.objects.active = driver
    yield {"action": "mouse", "x": x, "y": y}
    yield {"action": "key", "keys": ["x"], "pause": 0.5}
    yield {"action": "key", "keys": ["Return"], "pause": 0.5}
    yield from until(lambda: "Driver" not in bpy.context.scene.objects, 10, "X to delete the Empty")
    bake.last_bake.clear()
    yield from menu_search(win, vregion, "bake frames")
    yield from until(lambda: bake.last_bake.get("state") in ENDED, 60, "the bake to stop on the deleted Empty")
    record(deleted_state=bake.last_bake["state"], deleted_frames=drawn(tree))


Steps(run())
