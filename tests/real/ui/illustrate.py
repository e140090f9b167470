"""Real-UI test script: import the heart, start Illustrate the way a user does (invoke
with an event loop), hold its worker after two system iterations (the runner's test
hook: the run is mid-way whatever the machine's speed), check that another timer keeps
ticking, take a screenshot, press Esc through xdotool, check the outlines found so far
stay (their hidden lines removed), screenshot, then undo once and check the run is
gone (the sidebar says the ink changed since the run); a second run is stopped by editing the tree;
a third by Ctrl+Z, and a fourth is undone from a script (undone_while_running); a look
stopped by Esc clears the other look's strokes (look_stopped)."""
import os
import sys
import time

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from uikit import screen_xy  # noqa: E402
from uistep import EXT, Steps, record, start_with_example  # noqa: E402

ticks = []


def other_timer():
    ticks.append(time.monotonic())
    return 0.1


def strokes_of(name):
    obj = bpy.data.objects.get(name)
    if obj is None or obj.type != "GREASEPENCIL":
        return 0
    return sum(len(l.frames[0].drawing.strokes) for l in obj.data.layers if len(l.frames))


def length_of(name):
    """Total polyline length of the drawing (stitching may merge strokes; length stays)."""
    import numpy as np
    obj = bpy.data.objects.get(name)
    total = 0.0
    for layer in (obj.data.layers if obj is not None else []):
        if len(layer.frames):
            for st in layer.frames[0].drawing.strokes:
                p = np.array([q.position for q in st.points])
                total += float(np.linalg.norm(np.diff(p, axis=0), axis=1).sum()) if len(p) > 1 else 0.0
    return total


def run():
    win, view3d, region = yield from start_with_example("heart")
    tree = bpy.data.node_groups["heart"]
    tree.ink.grid_resolution = 20
    bpy.ops.ed.undo_push(message="imported")
    ill = sys.modules[EXT + ".operators.illustrate"]
    hold = sys.modules[EXT + ".pipeline.runner"].HOLD
    hold.arm(3)                              # after the initialisation and two iterations
    bpy.app.timers.register(other_timer, first_interval=0.1)
    yield 2.0
    started = time.monotonic()
    with bpy.context.temp_override(window=win, area=view3d, region=region):
        res = bpy.ops.blobtree_ink.illustrate("INVOKE_DEFAULT", tree_name="heart", request="OUTLINES")
    record(invoke_result=sorted(res), state_after_invoke=ill.last_run.get("state"))
    while not hold.reached.is_set():
        yield 0.1
    yield 0.5                                # a tick writes what the worker published
    ink = bpy.data.objects.get("heart Ink")
    if ink is not None:                      # frame the drawing as an artist would
        for o in bpy.context.view_layer.objects:
            o.select_set(o == ink)
        with bpy.context.temp_override(window=win, area=view3d, region=region):
            bpy.ops.view3d.view_selected()
    yield 1.0
    running = dict(ill.last_run)
    n_running = strokes_of("heart Ink")
    len_running = length_of("heart Ink")
    yield {"action": "screenshot", "name": "illustrate_running.png"}
    yield {"action": "key", "keys": ["Escape"], "pause": 0.5}
    for _ in range(100):                   # the worker removes the hidden lines, then the run ends
        if ill.last_run.get("state") != "running":
            break
        yield 0.1
    stopped = dict(ill.last_run)
    n_after = strokes_of("heart Ink")
    len_after = length_of("heart Ink")
    gaps = [b - a for a, b in zip(ticks, ticks[1:]) if a >= started]
    idle = [b - a for a, b in zip(ticks, ticks[1:]) if b < started]
    bpy.app.timers.unregister(other_timer)
    yield {"action": "screenshot", "name": "illustrate_stopped.png"}
    panels = sys.modules[EXT + ".operators.panels"]
    record(changed_before_undo=panels.changed_since(ill.last_run))
    with bpy.context.temp_override(window=win, area=view3d, region=region):
        bpy.ops.ed.undo()
    yield 0.5
    record(changed_after_undo=panels.changed_since(ill.last_run),
           strokes_after_undo=strokes_of("heart Ink"),
           ink_object_after_undo=bpy.data.objects.get("heart Ink") is not None,
           tree_after_undo="heart" in bpy.data.node_groups)
    # a second run, stopped by editing the tree
    hold.arm(2)
    with bpy.context.temp_override(window=win, area=view3d, region=region):
        bpy.ops.blobtree_ink.illustrate("INVOKE_DEFAULT", tree_name="heart", request="OUTLINES")
    while not hold.reached.is_set():
        yield 0.1
    tree = bpy.data.node_groups["heart"]            # undo replaced the data: fetch it again
    node = [n for n in tree.nodes if getattr(n, "kind", "") == "point"][0]
    node.radius = node.radius * 1.01
    for _ in range(100):                   # the next tick notices, the worker removes hidden lines and ends
        if ill.last_run.get("state") != "running":
            break
        yield 0.1
    hold.release()
    edited = dict(ill.last_run)
    record(edited_state=edited.get("state"))
    yield from undone_while_running(win, view3d, region, ill, hold)
    yield from look_stopped(win, view3d, region, ill, hold)
    record(running_state=running.get("state"), running_iterations=running.get("iterations", 0),
           strokes_while_running=n_running, stopped_state=stopped.get("state"),
           strokes_after_esc=n_after, length_while_running=len_running, length_after_esc=len_after,
           idle_timer_median_gap=sorted(idle)[len(idle) // 2] if idle else None, iterations_at_stop=stopped.get("iterations", 0),
           fraction_at_stop=stopped.get("fraction"), max_tick_ms=stopped.get("max_tick_ms"),
           ticks=stopped.get("ticks"), other_timer_ticks=len(gaps) + 1,
           other_timer_median_gap=sorted(gaps)[len(gaps) // 2] if gaps else None,
           other_timer_max_gap=max(gaps) if gaps else None)


def undone_while_running(win, view3d, region, ill, hold):
    """A third run, Ctrl+Z pressed while it runs: the key stops it as Esc does, keeping
    what it drew as one undo step, and Ctrl+Z again takes that back (the model stays).
    A fourth run undone from a script (as from the Edit menu): it ends writing nothing."""
    bpy.ops.ed.undo_push(message="edited")
    before = length_of("heart Ink")

    def started():
        hold.arm(3)
        with bpy.context.temp_override(window=win, area=view3d, region=region):
            bpy.ops.blobtree_ink.illustrate("INVOKE_DEFAULT", tree_name="heart", request="OUTLINES")
        while not hold.reached.is_set():
            yield 0.1
        yield 0.5

    def ended():
        for _ in range(100):
            if ill.last_run.get("state") != "running":
                break
            yield 0.1
    yield from started()
    x, y = screen_xy(win, region, region.width / 2, region.height / 2)
    yield {"action": "mouse", "x": x, "y": y, "pause": 0.2}
    yield {"action": "key", "keys": ["ctrl+z"], "pause": 0.5}
    yield from ended()
    record(undo_key_state=ill.last_run.get("state"), tree_after_undo_key="heart" in bpy.data.node_groups,
           length_before_undo_key=before, length_after_undo_key=length_of("heart Ink"))
    yield {"action": "key", "keys": ["ctrl+z"], "pause": 1.0}
    record(tree_after_second_undo="heart" in bpy.data.node_groups, length_after_second_undo=length_of("heart Ink"))
    yield from started()
    with bpy.context.temp_override(window=win, area=view3d, region=region):
        bpy.ops.ed.undo()
    yield from ended()
    hold.release()
    record(script_undo_state=ill.last_run.get("state"))


def look_stopped(win, view3d, region, ill, hold):
    """A Stippled look, then a Hatched look stopped with Esc: a stopped look is one drawing
    too, the stipples of the other look cleared (not left under the new one's lines)."""
    def look(preset):
        with bpy.context.temp_override(window=win, area=view3d, region=region):
            bpy.ops.blobtree_ink.illustrate("INVOKE_DEFAULT", tree_name="heart", preset=preset)
    look("STIPPLED")
    for _ in range(600):
        if ill.last_run.get("state") != "running":
            break
        yield 0.1

    def stipples():
        obj = bpy.data.objects.get("heart Ink")
        layer = obj.data.layers.get("Stipples") if obj is not None else None
        return len(layer.frames[0].drawing.strokes) if layer is not None and len(layer.frames) else 0
    record(stippled_state=ill.last_run.get("state"), stipples_before_hatched=stipples())
    hold.arm(3)
    look("HATCHED")
    while not hold.reached.is_set():
        yield 0.1
    yield {"action": "key", "keys": ["Escape"], "pause": 0.5}
    for _ in range(100):
        if ill.last_run.get("state") != "running":
            break
        yield 0.1
    hold.release()
    record(hatched_stopped_state=ill.last_run.get("state"), stipples_after_stopped_hatched=stipples())


Steps(run())
