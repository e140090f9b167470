"""Illustrate: the MASSRIS agents working on the active BlobTree, as a modal operator.

In the UI the agents step on a worker thread (agents.runner: pure numpy, no Blender
data) and a timer ticks; each tick only reads the latest snapshot, writes the strokes
found so far to the model's Grease Pencil object, and updates the progress bar and the
status text, so a tick takes milliseconds however slow an iteration is. Esc or right-click stops and keeps everything made so far; the whole run is one
undo step. Editing the tree during a run stops it. In background mode (`blender -b`)
and from scripts without an event loop, `execute` runs the stepper to completion.

Requests (MASSRIS Table 1): OUTLINES traces feature outlines; FIND_FEATURES explores a
region for more detail (and traces what it finds); PLACE_STROKES adds hatching and/or
stipples (the tree's settings) in a region; SINGLE_STROKE draws one smarticle stroke
from the 3D cursor. A region is the selected objects' bounds, else a sphere around the
3D cursor.
"""
import time

import bpy
from mathutils import Vector
import numpy as np

from ..agents import Region, Session, Settings
from ..agents.runner import Runner
from ..blackboard.view import View
from ..blobtree_nodes import preview
from ..blobtree_nodes.compile import TreeError, compile_tree
from ..blobtree_nodes.settings import style_of
from ..grease_pencil import render as R
from ..grease_pencil.writer import ink_object, write
from ..model import Evaluator
from ..strokes import StrokeSet, style as ST
from ..strokes.requests import final_strokes
from .common import context_tree

REQUESTS = [("OUTLINES", "Trace Feature Outlines", "Agents find and trace silhouettes and creases"),
            ("SINGLE_STROKE", "Create a Single Stroke", "One smarticle stroke from the 3D cursor"),
            ("PLACE_STROKES", "Place Strokes", "Hatching and stipples in a region"),
            ("FIND_FEATURES", "Find Features", "Explore a region for more detail")]
last_run = {}        # figures of the latest run (module state, read by the panel and tests)


def _eye(context, tree, ev):
    sc = context.scene
    if tree.ink.use_camera and sc.camera is not None:
        return np.array(sc.camera.matrix_world.translation)
    rv3d = getattr(context, "region_data", None)
    if rv3d is not None and hasattr(rv3d, "view_matrix"):
        inv = rv3d.view_matrix.inverted()
        if rv3d.is_perspective:
            return np.array(inv.translation)
    centre, radius, eye = R.plan_view(ev)
    return eye


def _light(context, centre, eye):
    """Towards the scene's light: a sun's direction, else the direction to the nearest
    other light; without a light, the upper left of the viewer."""
    lights = [o for o in context.scene.objects if o.type == "LIGHT" and not o.hide_render]
    suns = [o for o in lights if o.data.type == "SUN"]
    if suns:
        d = np.array(suns[0].matrix_world.to_3x3() @ Vector((0.0, 0.0, 1.0)))
    elif lights:
        pos = min((np.array(o.matrix_world.translation) for o in lights), key=lambda p: np.linalg.norm(p - centre))
        d = pos - centre
    else:
        return ST.default_light(centre, eye)
    n = np.linalg.norm(d)
    return d / n if n > 0 else ST.default_light(centre, eye)


def _region(context, tree):
    sel = [o for o in context.selected_objects if o.type not in ("GREASEPENCIL",)] \
        if hasattr(context, "selected_objects") else []
    if sel:
        pts = np.array([o.matrix_world @ Vector(c) for o in sel for c in o.bound_box])
        return Region(box=(pts.min(0), pts.max(0)))
    return Region(sphere=(np.array(context.scene.cursor.location), tree.ink.region_radius))


class BLOBTREE_INK_OT_illustrate(bpy.types.Operator):
    """Let the agents illustrate the BlobTree (Esc or right-click stops and keeps the strokes)"""
    bl_idname = "blobtree_ink.illustrate"
    bl_label = "Illustrate BlobTree"
    bl_options = {"REGISTER", "UNDO"}

    tree_name: bpy.props.StringProperty(name="Tree")
    request: bpy.props.EnumProperty(name="Request", items=REQUESTS, default="OUTLINES")

    # --- setting up ------------------------------------------------------------------
    def _start(self, context):
        self.tree = context_tree(context, self.tree_name)
        self.tree_key = self.tree.name
        self.model = compile_tree(self.tree)
        self.ev = Evaluator(self.model)
        s = self.tree.ink
        self.style = style_of(s)
        self.eye = _eye(context, self.tree, self.ev)
        self.session = Session(self.ev, View(eye=self.eye), Settings(resolution=s.grid_resolution,
                                                                     agents=s.agents, lod=s.lod, seed=s.seed))
        self.region = _region(context, self.tree) if self.request in ("PLACE_STROKES", "FIND_FEATURES") else None
        if self.request == "FIND_FEATURES":
            self.session.request("FIND_FEATURES", self.region)
        self.session.request("OUTLINES")
        self.edits0 = preview.edits(self.tree)
        self.obj_name = ink_object(f"{self.model.name} Ink").name
        centre, radius, _ = R.plan_view(self.ev)
        self.line_radius = 0.0025 * radius
        self.light = _light(context, centre, self.eye)
        self.cursor = np.array(context.scene.cursor.location)
        self.seed = s.seed
        self.tasks0 = max(self.session.tasks_left, 1)
        self.t_start = time.perf_counter()
        last_run.clear()
        last_run.update(iterations=0, ticks=0, max_tick_ms=0.0, state="running", tree=self.tree_key)

    def _write(self, strokes):
        write(ink_object(self.obj_name), strokes, frame=bpy.context.scene.frame_current)
        last_run["strokes"] = strokes.count()

    def _finalizer(self):
        """The pure finishing step, bound to plain values only (it runs on the worker)."""
        args = (self.session, self.request, self.style, self.eye, self.light, self.line_radius, self.seed,
                self.region, self.cursor)
        return lambda: final_strokes(*args)

    def _figures(self, progress):
        last_run.update(iterations=progress["iterations"], tasks_left=progress["tasks_left"],
                        outline_length=progress["outline_length"])
        return progress

    # --- running -----------------------------------------------------------------------
    def execute(self, context):
        try:
            self._start(context)
        except (LookupError, TreeError, ValueError) as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        self.session.run()
        self._figures(self.session.progress())
        strokes, warnings = self._finalizer()()
        self._write(strokes)
        self._report_done("done", warnings)
        return {"FINISHED"}

    def invoke(self, context, event):
        if bpy.app.background or context.window is None:
            return self.execute(context)
        try:
            self._start(context)
        except (LookupError, TreeError, ValueError) as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        # the agents step on a worker thread; each tick only shows their latest snapshot
        self.runner = Runner(self.session, finalize=self._finalizer()).start()
        self.shown = 0
        wm = context.window_manager
        self.timer = wm.event_timer_add(0.05, window=context.window)
        wm.progress_begin(0, 100)
        wm.modal_handler_add(self)
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        if event.type in {"ESC", "RIGHTMOUSE"} and event.value == "PRESS":
            return self._finish(context, "stopped")
        if event.type != "TIMER":
            return {"PASS_THROUGH"}
        t0 = time.perf_counter()
        tree = bpy.data.node_groups.get(self.tree_key)
        if tree is None or preview.edits(tree) != self.edits0:
            self.report({"WARNING"}, "the BlobTree changed: illustration stopped")
            return self._finish(context, "tree edited")
        try:
            self.runner.check()
        except RuntimeError as e:
            self.report({"ERROR"}, str(e))
            return self._finish(context, "failed")
        snap = self.runner.snapshot()
        if snap.final is not None:
            return self._finish(context, "done")
        if snap.version != self.shown:     # strokes as traced so far (hidden lines go at the end)
            self._write(StrokeSet.from_outlines(snap.outlines, self.line_radius))
            self.shown = snap.version
        pr = self._figures(snap.progress)
        done = 100.0 * (1.0 - pr["tasks_left"] / max(self.tasks0, pr["tasks_left"], 1))
        context.window_manager.progress_update(done)
        context.workspace.status_text_set(
            f"BlobTree Ink: iteration {pr['iterations']}, tasks left {pr['tasks_left']}, "
            f"outline length {pr['outline_length']:.3g}  (Esc: stop and keep)")
        tick_ms = 1000 * (time.perf_counter() - t0)
        last_run["ticks"] += 1
        last_run["max_tick_ms"] = max(last_run["max_tick_ms"], tick_ms)
        return {"RUNNING_MODAL"}

    def _finish(self, context, state):
        t0 = time.perf_counter()
        self.runner.stop()                 # the worker ends after its current iteration, unseen
        wm = context.window_manager
        wm.event_timer_remove(self.timer)
        wm.progress_end()
        context.workspace.status_text_set(None)
        snap = self.runner.snapshot()
        self._figures(snap.progress)
        warnings = []
        if state == "done":
            strokes, warnings = snap.final
            self._write(strokes)
        else:                              # keep what was made so far
            self._write(StrokeSet.from_outlines(snap.outlines, self.line_radius))
        last_run["finish_ms"] = 1000 * (time.perf_counter() - t0)
        self._report_done(state, warnings)
        return {"FINISHED"}                # keep what was made, as one undo step

    def cancel(self, context):
        """Blender cancels a modal operator when its window closes or a file loads: the
        worker stops and the timer goes (no drawing: the data may be gone)."""
        self.runner.stop()
        context.window_manager.event_timer_remove(self.timer)
        context.window_manager.progress_end()
        last_run["state"] = "cancelled"

    def _report_done(self, state, warnings=()):
        last_run["state"] = state
        for w in warnings:
            self.report({"WARNING"}, w)
        self.report({"INFO"}, f"Illustration {state}: {last_run.get('strokes', 0)} strokes after "
                              f"{last_run['iterations']} iterations")


classes = (BLOBTREE_INK_OT_illustrate,)
