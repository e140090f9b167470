"""Illustrate: one of MASSRIS's Table 1 requests on a BlobTree, through the
illustration pipeline (pipeline.Illustration).

In the UI the pipeline steps on a worker thread (pipeline.Runner: pure numpy, no
Blender data), from the polygonisation on, and a timer ticks: each tick only reads the
latest result, writes it to the model's Grease Pencil object, and updates the progress
bar and the status text, so a tick takes milliseconds however slow a step is. Esc or
right-click stops and keeps everything made so far (the worker removes the hidden lines
of the outlines traced so far first); the whole run is one undo step. Editing the tree
during a run stops it. In background mode (`blender -b`) and from scripts without an
event loop, `execute` runs the same pipeline to the end.

Requests: OUTLINES traces feature outlines; FIND_FEATURES explores a region for more
detail (and traces what it finds); PLACE_STROKES draws the style's stroke layers in a
region; SINGLE_STROKE draws one smarticle stroke from the 3D cursor. A region is the
selected objects' bounds, else the whole model, or a sphere around the 3D cursor (the
tree's Region setting). Each request writes only its own layers
(pipeline.Job.owned_layers). With ``preset``, the tree's style is set to that look
first and its strokes are drawn (with the outlines where none are drawn yet), in the
same undo step. With the tree's Paper on, the scene is put on white paper.
"""
import functools
import time
import traceback
from dataclasses import replace

import bpy
import numpy as np
from mathutils import Vector

from .. import pipeline as PL
from ..blobtree_nodes import changes, preview
from ..blobtree_nodes.compile import TreeError, compile_document, same_model
from ..blobtree_nodes.settings import PRESETS, PRESET_TIPS, apply_preset, style_of
from ..grease_pencil import views
from ..grease_pencil.writer import ink_object, read_layer, stroke_count, write, write_layer
from ..strokes.data import LAYER_OF_KIND, STROKE_LAYERS
from ..model import Evaluator
from . import frames as FR
from . import jobs, region_overlay, undo_guard
from .common import context_tree, ink_name

REQUESTS = [("OUTLINES", "Trace Feature Outlines",
             "The agents find and trace the silhouettes and creases, hidden lines removed (replaces the outline "
             "layers)"),
            ("SINGLE_STROKE", "Create a Single Stroke",
             "One smarticle stroke from the surface point nearest the 3D cursor (added to the Single Strokes "
             "layer)"),
            ("PLACE_STROKES", "Place Strokes",
             "The style's strokes (hatching, chains, short strokes, stipples) in the region (replaces those "
             "layers only)"),
            ("FIND_FEATURES", "Find Features",
             "Agents explore the region for smaller features and trace what they find (replaces the outline "
             "layers)")]
REQUEST_TIPS = {k: tip for k, _, tip in REQUESTS}
NO_PRESET = "NONE"
TICK = 0.05                 # seconds between the modal timer's ticks
WRITE_EVERY = 0.25          # seconds between writes of a run's progress, at least ...
DRAW_SHARE = 0.25           # ... and long enough that redrawing what was written takes at most this share of
                            # the time (software GL redraws a viewport with ink in about 0.2 s)
CANCEL_WAIT = 2.0           # seconds a cancelled run waits for its worker
START_ERRORS = (LookupError, TreeError, PL.JobError, PL.NothingToDraw, ValueError)   # what the artist can mend
last_run = {}               # figures of the latest run (module state, read by the panel and tests)


class BLOBTREE_INK_OT_illustrate(bpy.types.Operator):
    """Let the agents illustrate the BlobTree (Esc or right-click stops and keeps the strokes)"""
    bl_idname = "blobtree_ink.illustrate"
    bl_label = "Illustrate BlobTree"
    bl_options = {"REGISTER", "UNDO"}

    tree_name: bpy.props.StringProperty(name="Tree", options={"SKIP_SAVE"},
                                        description="The BlobTree node tree (empty: the active one)")
    request: bpy.props.EnumProperty(name="Request", items=REQUESTS, default="OUTLINES", options={"SKIP_SAVE"})
    preset: bpy.props.EnumProperty(name="Preset", default=NO_PRESET, options={"SKIP_SAVE"},
                                   description="Set the tree's style to this look first and draw it",
                                   items=[(NO_PRESET, "None", "Draw with the tree's style as it is")] +
                                         [(k, k.replace("_", " ").title(), PRESET_TIPS[k]) for k in PRESETS])

    @classmethod
    def description(cls, context, properties):
        if properties.preset != NO_PRESET:
            return (f"Draw the {properties.preset.replace('_', ' ').lower()} look: {PRESET_TIPS[properties.preset]}. "
                    "It replaces the strokes another look drew (Ctrl+Z brings them back); traced lines and "
                    "single strokes stay")
        return REQUEST_TIPS[properties.request]

    # --- setting up ------------------------------------------------------------------
    def _requests(self, context, tree, inverse):
        """The pipeline requests of this run (a preset: its strokes, with the outlines
        where the outline layers have none yet, or the outlines alone; :meth:`_start`
        adds the outlines where they were drawn for another viewpoint)."""
        kind = self.request
        if self.preset != NO_PRESET:
            kind = "OUTLINES" if self.preset == "OUTLINES" else "PLACE_STROKES"
        region = jobs.request_region(context, tree, inverse) if kind in ("PLACE_STROKES", "FIND_FEATURES") else None
        cursor = jobs.to_model(inverse, context.scene.cursor.location) if kind == "SINGLE_STROKE" else None
        requests = [PL.Request(kind, region, cursor)]
        drawn = stroke_count(bpy.data.objects.get(ink_name(tree)), LAYER_OF_KIND.values(), context.scene.frame_current)
        if self.preset not in (NO_PRESET, "OUTLINES") and drawn == 0:
            requests.insert(0, PL.Request("OUTLINES"))
        return tuple(requests)

    def _start(self, context):
        tree = context_tree(context, self.tree_name)
        self.tree_key = tree.name
        ink = tree.ink
        if self.preset != NO_PRESET:
            apply_preset(ink, self.preset)
        # the document too: an edit that leaves it as it is does not stop the run
        model, self.document = compile_document(tree)
        self.placement = jobs.placement(tree)
        inverse = self.placement.inverted_safe()
        self.from_camera = ink.use_camera
        self.notes = []
        framing = functools.cache(lambda: PL.bounds(Evaluator(model)))   # centre and radius, once asked for
        if ink.use_camera:
            eye = jobs.camera_eye(context.scene)
            off = jobs.off_camera(context.scene, tree)
            if off and not PL.inside(Evaluator(model), np.array(inverse @ Vector(eye), float)):
                self.notes.append(off)     # (a camera inside the model: the run's own warning says so, last)
        else:
            centre, radius = framing()
            eye = jobs.viewport_eye(context, np.array(self.placement @ Vector(centre), float),
                                    jobs.scale_of(self.placement) * radius)
            if eye is None:
                raise PL.JobError("From Camera is off and there is no 3D viewport to illustrate from: run it "
                                  "from the 3D viewport, or switch From Camera on")
        solids, broken = jobs.occluders(context.scene, tree)
        self.notes += [jobs.hidden_by_note(broken)] if broken else []
        job = jobs.job(model, context.scene, style_of(ink), jobs.tree_settings(ink),
                       self._requests(context, tree, inverse), ink.seed, eye=eye, inverse=inverse, occluders=solids)
        obj, frame = bpy.data.objects.get(ink_name(tree)), context.scene.frame_current
        self.unfit = {}                 # the layers a look clears once done: {layer: why}
        if obj is not None:             # what is drawn already, and for which viewpoint and model
            look = self.preset != NO_PRESET
            elsewhere = jobs.drawn_elsewhere(obj, job, frame, *framing(), context.scene, tree)
            if look and self.preset != "OUTLINES" and not job.wants_outline_layers() \
                    and set(jobs.traced_layers(job)) & set(elsewhere):
                job = replace(job, requests=(PL.Request("OUTLINES"),) + job.requests)    # a look is one drawing
                elsewhere = {n: w for n, w in elsewhere.items() if n not in job.owned_layers()}
            if look:                    # ... and clears the strokes another look drew (the truer reason where
                others = [n for n in STROKE_LAYERS if n not in job.owned_layers()       # they were drawn elsewhere too)
                          and n in obj.data.layers and FR.strokes_at(obj.data.layers[n], frame)]
                self.unfit = {**elsewhere, **dict.fromkeys(others, jobs.ANOTHER_LOOK)}
            else:
                note = jobs.elsewhere_note(elsewhere, job)
                self.notes += [note] if note else []
        if obj is not None and job.stroke_switches() and not job.wants_outline_layers():
            job = replace(job, lines=tuple(s for n in jobs.traced_layers(job) if n in obj.data.layers
                                           for s in read_layer(obj, n, frame)))     # the strokes end at them
        self.illustration = PL.Illustration(job)
        self.edits0 = changes.edits(tree)
        jobs.on_paper(context, tree)
        obj = ink_object(ink_name(tree), preview.tree_collection(tree))
        jobs.attach(obj, tree)
        self.obj_name = obj.name
        self.frame = context.scene.frame_current

        self.t_start = time.perf_counter()
        last_run.clear()
        last_run.update(iterations=0, ticks=0, max_tick_ms=0.0, state="running", tree=self.tree_key,
                        fraction=0.0, stage="init")

    def _write(self, result):
        obj = ink_object(self.obj_name)
        write(obj, result, frame=self.frame)
        # the drawing's strokes, those the run kept (the outlines a look reuses) too: the
        # same look on the same view says the same number however it came about
        shown = FR.shown_counts(obj, self.frame)
        last_run["strokes"] = sum(shown.get(name, 0) for name in FR.DRAWN)

    def _clear_unfit(self):
        """A look that ran to its end, or was stopped (Esc keeps what it drew), is one
        drawing: the layers it left that were drawn for another viewpoint or model, or by
        another look, are cleared (said in the report; Ctrl+Z brings them back)."""
        if self.unfit:
            obj = ink_object(self.obj_name)
            for name in self.unfit:
                write_layer(obj, name, [], frame=self.frame)
            views.forget(obj, list(self.unfit), self.frame)
            self.notes.append(jobs.cleared_note(self.unfit))

    def _hold(self, result):
        """On an ink with drawings on later frames (a bake's), the layers written here end
        where those begin (frames.hold_to_next); a look says those frames keep their own."""
        obj = bpy.data.objects.get(self.obj_name)
        later = FR.hold_to_next(obj, list(result.owned), self.frame) if obj else []
        if later and self.preset != NO_PRESET:
            self.notes.append(f"frames {FR.spans(later)} keep their own drawings: bake them again to draw them "
                              "in this look")

    def _figures(self, progress):
        last_run.update(iterations=progress.iterations, outline_length=progress.outline_length,
                        fraction=progress.fraction, stage=progress.stage)
        return progress

    def _failed(self, e, level="ERROR"):
        """A run that cannot start: said (an error for scripts and background runs; in the
        UI a warning, in the status bar: an error's popup would take the keys, and the
        sidebar already shows what is wrong), nothing drawn."""
        self.report({level}, str(e))
        return {"CANCELLED"}

    # --- running -----------------------------------------------------------------------
    def execute(self, context):
        try:
            self._start(context)
        except START_ERRORS as e:
            return self._failed(e)
        try:
            result = self.illustration.run()
        except (PL.JobError, PL.NothingToDraw) as e:    # (a light inside the model: found as it begins; nothing drawn)
            return self._failed(e)
        finally:
            region_overlay.show(self.tree_key, [])
        self._figures(result.progress)
        self._write(result)
        self._clear_unfit()
        self._hold(result)
        self._report_done("done", result.warnings + self.notes)
        return {"FINISHED"}

    def invoke(self, context, event):
        if bpy.app.background or context.window is None:
            return self.execute(context)
        try:
            self._start(context)
        except START_ERRORS as e:
            return self._failed(e, "WARNING")
        self.runner = PL.Runner(self.illustration).start()
        self.undo_keys, self.undos = undo_guard.undo_keys(context), undo_guard.undos()
        self.undo_stopped = self.ended = False
        self.shown = None
        self.stopping = None
        self.last_tick = time.monotonic()
        self.next_write = self.last_tick
        self.wrote = False
        wm = context.window_manager
        self.timer = wm.event_timer_add(TICK, window=context.window)
        wm.progress_begin(0, 100)
        wm.modal_handler_add(self)
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        try:
            return self._tick(context, event)
        except Exception as e:             # a tick that fails ends the run, said and printed
            traceback.print_exc()
            self.report({"ERROR"}, f"the illustration stopped: {e!r}")
            return {"FINISHED"} if self.ended else self._end(context, "failed")     # (ending it failed: once)

    def _tick(self, context, event):
        if undo_guard.undos() != self.undos:              # undone from a menu or a script: the data is gone
            return self._undone(context)
        undo = undo_guard.undo_key(event, self.undo_keys)
        if (undo or event.type in {"ESC", "RIGHTMOUSE"} and event.value == "PRESS") and self.stopping is None:
            self.stopping = "stopped"
            self.stopped_at = last_run.get("fraction", 0.0)      # the share done when Esc was pressed
            self.runner.stop()             # the worker draws the visible outlines so far, then ends
            if undo:                       # said now, and last when the run ends (the status bar's)
                self.report({"INFO"}, UNDO_STOPS)
                self.undo_stopped = True
            return {"RUNNING_MODAL"}
        if undo:                           # no undo under a run (see undo_guard)
            return {"RUNNING_MODAL"}
        if event.type != "TIMER":
            return {"PASS_THROUGH"}
        t0 = time.perf_counter()
        tree = bpy.data.node_groups.get(self.tree_key)
        if self.stopping is None and tree is not None and changes.edits(tree) != self.edits0 \
                and same_model(tree, self.document):
            self.edits0 = changes.edits(tree)   # (a change of no value of the model, e.g. the run's own writes)
        if self.stopping is None and (tree is None or changes.edits(tree) != self.edits0):
            self.report({"WARNING"}, "the BlobTree changed: illustration stopped")
            self.stopping = "tree edited"
            self.runner.stop()
        if self.runner.finished:
            return self._end(context, self.stopping or "done")
        # the time since the last tick beyond the timer's interval went to the UI, mostly
        # to redrawing what the last write changed: the next write waits for it
        now = time.monotonic()
        if self.wrote:
            self.next_write = max(self.next_write, now + (now - self.last_tick - TICK) * (1 / DRAW_SHARE - 1))
            self.wrote = False
        self.last_tick = now
        result = self.runner.latest()
        if result is not None and result is not self.shown and now >= self.next_write:
            self._show(context, result)
            self.next_write, self.wrote = now + WRITE_EVERY, True
        tick_ms = 1000 * (time.perf_counter() - t0)
        last_run["ticks"] += 1
        last_run["max_tick_ms"] = max(last_run["max_tick_ms"], tick_ms)
        return {"RUNNING_MODAL"}

    def _show(self, context, result):
        """Write a result (once: a single stroke is added to its layer), its figures and
        its region in the viewport."""
        self._write(result)
        region_overlay.show(self.tree_key, [result.region] if result.region is not None else [], self.placement)
        self.shown = result
        pr = self._figures(result.progress)
        context.window_manager.progress_update(100.0 * pr.fraction)
        what = "stopping: removing hidden lines" if self.stopping else pr.stage
        agents = f"; iteration {pr.iterations}" if pr.iterations else ""
        context.workspace.status_text_set(
            f"BlobTree Ink: {100 * pr.fraction:.0f} % ({what}, stage {min(pr.stage_index + 1, pr.stages)} "
            f"of {pr.stages}{agents})  Esc: stop and keep")

    def _end(self, context, state):
        self.ended = True
        t0 = time.perf_counter()
        try:
            self.runner.join()
            self.runner.check()
        except PL.RunnerError as e:
            self.report({"ERROR"}, str(e))
            state = "failed"
        wm = context.window_manager
        wm.event_timer_remove(self.timer)
        wm.progress_end()
        context.workspace.status_text_set(None)
        region_overlay.show(self.tree_key, [])
        result = self.runner.latest()
        warnings = []
        if result is not None and state != "failed":
            if result is not self.shown:
                self._write(result)        # what was made, kept
            self._figures(result.progress)
            if state == "stopped":         # how far it had come when Esc was pressed
                last_run["fraction"] = min(last_run["fraction"], self.stopped_at)
            if state in ("done", "stopped"):
                self._clear_unfit()
            self._hold(result)
            warnings = result.warnings
        last_run["finish_ms"] = 1000 * (time.perf_counter() - t0)
        stopped_by_undo = [UNDO_STOPS] if self.undo_stopped else []
        self._report_done(state, warnings + self.runner.notes + self.notes + stopped_by_undo,
                          camera_hint(context, self.from_camera))
        return {"FINISHED"}                # keep what was made, as one undo step

    def cancel(self, context):
        """Blender cancels a modal operator when its window closes or a file loads: the
        worker is asked to end after its current step (it touches no Blender data, so
        the UI waits for it only briefly) and the timer goes; nothing is drawn (the data
        may be gone)."""
        self._drop(context, "cancelled")

    def _undone(self, context):
        """An undo or redo while the run went on restored data from before it (undo_guard):
        the run ends as a cancelled one, writing nothing into what is there now."""
        self._drop(context, "undone")
        self.report({"WARNING"}, "an undo while the illustration ran took back what it was drawing on: "
                                 "nothing drawn")
        return {"CANCELLED"}

    def _drop(self, context, state):
        self.runner.cancel()
        try:
            self.runner.join(CANCEL_WAIT)
        except PL.RunnerError as e:
            print(f"BlobTree Ink: {e}; it ends on its own")
        finally:
            context.window_manager.event_timer_remove(self.timer)
            context.window_manager.progress_end()
            if context.workspace is not None:
                context.workspace.status_text_set(None)
            region_overlay.show(self.tree_key, [])
            last_run["state"] = state

    def _report_done(self, state, warnings=(), hint=""):
        """The run's summary, then its warnings: the status bar shows the last report, so
        a warning is not hidden behind the summary."""
        last_run.update(state=state, warnings=list(warnings))
        obj = bpy.data.objects.get(self.obj_name)
        if obj is not None:                # what it left, for the sidebar to tell an undone run
            last_run["left"] = {"object": obj.name, "frame": self.frame, "counts": FR.shown_counts(obj, self.frame)}
        traced = f", the outlines after {last_run['iterations']} iterations" if last_run["iterations"] else ""
        n = last_run.get("strokes", 0)
        self.report({"INFO"}, f"Illustration {state}: {n} stroke{'' if n == 1 else 's'}{traced}{hint}")
        for w in warnings:
            self.report({"WARNING"}, w)


UNDO_STOPS = "Undo stopped the illustration, keeping what it drew as one step: undo again to take it back"


def camera_hint(context, from_camera):
    """What the report adds when the ink was drawn for the scene camera while the 3D
    viewport it was asked from looks from elsewhere (its lines then lie off the view's
    outlines, and hidden ones can show): how to see it as drawn."""
    r3d = getattr(getattr(context, "space_data", None), "region_3d", None)
    if from_camera and r3d is not None and r3d.view_perspective != "CAMERA":
        return "; drawn as the scene camera sees it (Numpad 0 looks through it)"
    return ""


classes = (BLOBTREE_INK_OT_illustrate,)
