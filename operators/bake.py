"""Bake: a tree illustrated at every frame of a range, each frame's drawing a Grease
Pencil keyframe of its ink's layers (ordinary, editable Grease Pencil), through the
one illustration pipeline, each frame going on from the last (pipeline.continuation:
where the model and the view stay, what was found is kept). In the UI each frame's
pipeline runs on a worker thread
while the timer shows the progress; Esc keeps the frames finished so far. In
background mode and from scripts it runs to the end in `execute`. The whole bake is
one undo step; baking again replaces only the frames and layers it makes. The frame
after the range shows no ink (frames.end_hold), not the last frame held. A frame that
fails (the tree does not compile then, an object it follows is gone) ends the bake
with a message naming it, the frames before it kept.

    bpy.ops.blobtree_ink.bake(tree_name="pear", frame_start=1, frame_end=24)
    bpy.ops.blobtree_ink.bake(tree_name="pear")      # the tree's bake range (the scene's by default)
"""
import bpy

from .. import pipeline as PL
from ..blobtree_nodes.animation import DriverError
from ..blobtree_nodes.compile import TreeError
from ..blobtree_nodes.settings import bake_range
from . import frames as FR
from . import jobs, undo_guard
from .common import context_tree

TICK = 0.05
ERRORS = (TreeError, DriverError, FR.FrameError, PL.JobError, PL.NothingToDraw, LookupError, ValueError)
last_bake = {}                # figures of the latest bake (module state, read by tests)


class BLOBTREE_INK_OT_bake(bpy.types.Operator):
    """Illustrate every frame of a range as Grease Pencil keyframes (Esc keeps the frames finished)"""
    bl_idname = "blobtree_ink.bake"
    bl_label = "Bake BlobTree Illustration"
    bl_options = {"REGISTER", "UNDO"}

    tree_name: bpy.props.StringProperty(name="Tree", options={"SKIP_SAVE"},
                                        description="The BlobTree node tree (empty: the active one)")
    # unset, each call takes the tree's bake range (never the last call's); once resolved
    # they hold the range baked, which Adjust Last Operation shows and bakes again
    frame_start: bpy.props.IntProperty(name="Start", default=1, options={"SKIP_SAVE"},
                                       description="First frame to bake (unset: the tree's bake range)")
    frame_end: bpy.props.IntProperty(name="End", default=250, options={"SKIP_SAVE"},
                                     description="Last frame to bake (unset: the tree's bake range)")

    def _start(self, context):
        tree = context_tree(context, self.tree_name)
        self.tree_key = tree.name
        start, end = bake_range(tree.ink, context.scene)
        if self.properties.is_property_set("frame_start"):
            start = self.frame_start
        if self.properties.is_property_set("frame_end"):
            end = self.frame_end
        self.frames = list(FR.frame_range(start, end))
        self.frame_start, self.frame_end = start, end
        jobs.on_paper(context, tree)
        self.followed = FR.followed_objects(bpy.data.node_groups[self.tree_key])
        self.scene = context.scene
        self.frame_was = self.scene.frame_current
        self.done = []
        self.previous = None              # what the last frame's illustration left this one's
        # frames are seen by the scene's camera; without one, from the pipeline's three-quarter view
        self.note = "" if self.scene.camera is not None else \
            "the scene has no camera: each frame is seen from a three-quarter view of the model"
        last_bake.clear()
        last_bake.update(state="running", frames=[], tree=self.tree_key, note=self.note)
        self.began = True                 # the figures are this bake's from here on

    def _job(self, frame):
        """Go to a frame and make its job (on the main thread: it reads the scene)."""
        self.scene.frame_set(frame)
        tree = bpy.data.node_groups.get(self.tree_key)
        if tree is None:
            raise FR.FrameError(f"frame {frame}: the BlobTree '{self.tree_key}' is gone")
        FR.check_followed(tree, self.followed, frame)
        try:
            return FR.frame_job(tree, self.scene)
        except (TreeError, DriverError) as e:
            raise FR.FrameError(f"frame {frame}: {e}") from None

    def _write(self, frame, result):
        self.ink = FR.write_frame(bpy.data.node_groups[self.tree_key], result, frame).name
        self.done.append(frame)
        last_bake["frames"] = list(self.done)

    def _finish(self, state, error=None, undone=False):
        self.scene.frame_set(self.frame_was)
        ink = bpy.data.objects.get(self.ink) if self.done else None
        if ink is not None:               # the frames after it show no ink, not the last one held
            FR.end_hold(ink, self.done[-1])
        last_bake["state"] = state
        if error is not None:
            self.report({"ERROR"}, f"{error}; frames {self._span()} are baked" if self.done else str(error))
        else:
            done = f"Bake {state}: frames {self._span()}" if self.done else f"Bake {state}: no frame"
            done += " (by undo, keeping them as one step: undo again to take them back)" if undone and self.done else ""
            self.report({"WARNING"} if self.note else {"INFO"}, f"{done} ({self.note})" if self.note else done)
        return {"FINISHED"}               # what was baked is kept, as one undo step

    def _span(self):
        return f"{self.done[0]}-{self.done[-1]}" if len(self.done) > 1 else str(self.done[0])

    # --- background: every frame in turn ------------------------------------------------
    def execute(self, context):
        try:
            self._start(context)
        except ERRORS as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        wm = None if bpy.app.background else context.window_manager     # a redo in the UI: the cursor's counter
        if wm is not None:
            wm.progress_begin(0, len(self.frames))
        try:
            for k, frame in enumerate(self.frames):
                try:
                    job, _ = self._job(frame)
                    ill = PL.Illustration(job, previous=self.previous, remember=True)
                    result = ill.run()
                    self.previous = ill.continuation()
                except ERRORS as e:
                    error = e if isinstance(e, FR.FrameError) else FR.FrameError(f"frame {frame}: {e}")
                    return self._finish("failed", error)
                self._write(frame, result)
                if wm is not None:
                    wm.progress_update(k + 1)
            return self._finish("done")
        finally:
            if wm is not None:
                wm.progress_end()

    # --- the UI: each frame's pipeline on a worker, a timer showing the progress ---------
    def invoke(self, context, event):
        if bpy.app.background or context.window is None:
            return self.execute(context)
        try:
            self._start(context)
            self._next_frame()
        except ERRORS as e:
            self.report({"ERROR"}, str(e))
            if getattr(self, "scene", None) is not None:
                self.scene.frame_set(self.frame_was)
            if getattr(self, "began", False):            # its first frame failed: no modal run
                last_bake["state"] = "failed"
            return {"CANCELLED"}
        self.undo_keys, self.undos = undo_guard.undo_keys(context), undo_guard.undos()
        wm = context.window_manager
        self.timer = wm.event_timer_add(TICK, window=context.window)
        wm.progress_begin(0, 100)
        wm.modal_handler_add(self)
        return {"RUNNING_MODAL"}

    def _next_frame(self):
        self.frame = self.frames[len(self.done)]
        job, _ = self._job(self.frame)
        self.runner = PL.Runner(PL.Illustration(job, previous=self.previous, remember=True)).start()

    def modal(self, context, event):
        if undo_guard.undos() != self.undos:  # undone from a menu or a script: the frames baked are gone
            self._drop(context, "undone")
            self.report({"WARNING"}, "an undo while the bake ran took back the frames it baked: nothing baked")
            return {"CANCELLED"}
        undo = undo_guard.undo_key(event, self.undo_keys)
        if undo or event.type in {"ESC", "RIGHTMOUSE"} and event.value == "PRESS":
            self.runner.cancel()              # the frame under way is not kept
            return self._end(context, "stopped", undone=undo)
        if event.type != "TIMER" or not self.runner.finished:
            if event.type == "TIMER":
                self._progress(context)
            return {"PASS_THROUGH"}
        try:
            self.runner.join()
            self.runner.check()
        except PL.RunnerError as e:
            return self._end(context, "failed", e)
        self._write(self.frame, self.runner.latest())
        self.previous = self.runner.illustration.continuation()
        if len(self.done) == len(self.frames):
            return self._end(context, "done")
        try:
            self._next_frame()
        except ERRORS as e:
            return self._end(context, "failed", e)
        self._progress(context)
        return {"RUNNING_MODAL"}

    def _progress(self, context):
        latest = self.runner.latest()
        within = latest.progress.fraction if latest is not None else 0.0
        share = (len(self.done) + within) / len(self.frames)
        context.window_manager.progress_update(100.0 * share)
        context.workspace.status_text_set(
            f"BlobTree Ink bake: frame {self.frame} ({len(self.done) + 1} of {len(self.frames)}), "
            f"{100 * share:.0f} %  Esc: stop and keep the frames baked")

    def _end(self, context, state, error=None, undone=False):
        try:
            self.runner.join()
        except PL.RunnerError as e:
            error = error or e
        wm = context.window_manager
        wm.event_timer_remove(self.timer)
        wm.progress_end()
        context.workspace.status_text_set(None)
        return self._finish(state, error, undone)

    def cancel(self, context):
        """The window closed or a file loaded: the frame under way is dropped (its worker
        touches no Blender data; the UI waits for it only briefly)."""
        self._drop(context, "cancelled")

    def _drop(self, context, state):
        """The run ends touching no Blender data (it may be gone), the frame under way dropped."""
        self.runner.cancel()
        try:
            self.runner.join(2.0)
        except PL.RunnerError as e:
            print(f"BlobTree Ink: {e}; it ends on its own")
        finally:
            context.window_manager.event_timer_remove(self.timer)
            context.window_manager.progress_end()
            if context.workspace is not None:
                context.workspace.status_text_set(None)
            last_bake["state"] = state


classes = (BLOBTREE_INK_OT_bake,)
