"""Rendering frames (`blender -b file.blend -a`, Render Animation, Render Image): each
frame a render reaches is illustrated before it renders, through the pipeline, for
every tree drawn in the scene (its ink or its preview is in it) with its *Illustrate
Rendered Frames* on, unless the ink already has a drawing of that frame made otherwise
(a bake, the artist's own run at that frame), or shows one, its own or held over from
an earlier frame, made from all this frame's job is made from (model, light, style,
seed, settings) for the very same eye (a still model drawn once, seen by a still
camera): those are used as they are. A bake's or the artist's drawing drawn for another
model or viewpoint than the frame's is rendered as it is, and the console says so.
The frame is illustrated as the render's depsgraph evaluates it (objects, animation),
in the frame change handler the render calls before it renders the frame."""
import traceback

import bpy

from .. import pipeline as PL
from ..blobtree_nodes import handlers
from ..blobtree_nodes.animation import DriverError
from ..blobtree_nodes.compile import TreeError
from ..grease_pencil import views
from ..model import Evaluator
from . import frames as FR
from . import jobs
from .common import blobtrees, ink_name

_rendering = []                # a render is under way (between its init and its end)
_drew = []                     # (tree, frame) drawn by the render under way
_undo_wanted = []              # a render drew frames: the main thread's timer makes them an undo step
UNDO_POLL = 0.5                # seconds between the timer's looks
_previous = {}                 # tree name -> what its last rendered frame left the next (during a render)
_warned = []                   # (tree, frame) whose kept drawing the render under way said does not fit
drawn = []                     # (tree, frame) drawn by renders in this session (for tests and the console)


def illustrate(scene, depsgraph=None):
    """Illustrate the scene's frame for every tree that wants it; returns the trees drawn."""
    frame = scene.frame_current
    done = []
    compiled = FR.Compiled(depsgraph)          # each tree compiled once, to draw it and to hide the others
    for tree in blobtrees():
        if not tree.ink.render_frames or not jobs.in_scene(tree, scene):
            continue
        kept = frame in FR.drawn_frames(tree) and frame not in FR.rendered_frames(tree)
        try:
            job, _ = FR.frame_job(tree, scene, depsgraph, compiled)
            if kept:                           # a bake's or the artist's: used as it is, said when it no longer fits
                _say_unfit(tree, job, frame, scene, depsgraph)
                continue
            if FR.holds(tree, job, frame):     # a drawing made from all this frame's job is: used as it is
                continue
            ill = PL.Illustration(job, previous=_previous.get(tree.name), remember=True)
            result = ill.run()
            _previous[tree.name] = ill.continuation()
        except (TreeError, DriverError, PL.JobError, PL.NothingToDraw, ValueError) as e:
            print(f"BlobTree Ink: frame {frame} of '{tree.name}' not illustrated: {e}")
            continue
        FR.write_frame(tree, result, frame, rendered=True)
        drawn.append((tree.name, frame))
        _drew.append((tree.name, frame))
        done.append(tree.name)
    return done


def _say_unfit(tree, job, frame, scene, depsgraph=None):
    """Print (once a render) which layers of a drawing the render keeps were drawn for
    another model or viewpoint than the frame's, or before the models in front of them
    moved or changed."""
    obj = bpy.data.objects.get(ink_name(tree))
    if obj is None or (tree.name, frame) in _warned:
        return
    layers = job.owned_layers()
    unfit = dict.fromkeys(views.other_model(obj, layers, frame, jobs.model_key(job)), views.MODEL)
    if not unfit and (job.view is None or not views.drawn_at(obj, layers, frame, job.view.eye)):
        centre, radius = PL.bounds(Evaluator(job.model))        # (only to tell another viewpoint)
        unfit = views.unfit(obj, layers, frame, PL.view_eye(job.view, centre, radius), centre)
    if not unfit:
        unfit = dict.fromkeys(jobs.moved_hiders(obj, job, layers, frame, scene, tree, depsgraph), jobs.HIDDEN)
    if unfit:
        _warned.append((tree.name, frame))
        said = "; ".join(f"{name} {jobs.WHY[why][0]}" for name, why in unfit.items())
        print(f"BlobTree Ink: frame {frame} of '{tree.name}' is rendered with the drawing it has: {said} "
              "(bake again, or clear the frame, to draw it anew)")


@bpy.app.handlers.persistent
def _render_init(*_args):
    _rendering[:] = [True]
    _previous.clear()
    _drew.clear()
    _warned.clear()


@bpy.app.handlers.persistent
def _render_end(*_args):
    if _drew:
        _undo_wanted[:] = [True]
    _rendering.clear()
    _previous.clear()
    _drew.clear()


def _undo_step():
    """An undo step for the frames a render in the UI drew (a render is no operator:
    without it, the next Ctrl+Z would go back past them, to before the render). A
    timer of the main thread's, registered once: a render's handlers may run on its
    own thread, where Blender data and the undo stack are not to be touched."""
    if _undo_wanted and not _rendering:
        _undo_wanted.clear()
        wm = bpy.context.window_manager
        if wm is not None and wm.windows:
            with bpy.context.temp_override(window=wm.windows[0]):
                bpy.ops.ed.undo_push(message="BlobTree Ink: frames drawn by the render")
    return UNDO_POLL


@bpy.app.handlers.persistent
def _frame_changed(scene, depsgraph=None):
    if not _rendering:
        return
    try:
        illustrate(scene, depsgraph)
    except Exception:                   # a handler's failure must not stop the render: said, with its traceback
        print(f"BlobTree Ink: frame {scene.frame_current} could not be illustrated:")
        traceback.print_exc()


HANDLERS = ((bpy.app.handlers.render_init, _render_init), (bpy.app.handlers.render_complete, _render_end),
            (bpy.app.handlers.render_cancel, _render_end), (bpy.app.handlers.frame_change_post, _frame_changed))


def register():
    handlers.attach(HANDLERS)
    if not bpy.app.background and not bpy.app.timers.is_registered(_undo_step):
        bpy.app.timers.register(_undo_step, first_interval=UNDO_POLL, persistent=True)


def unregister():
    handlers.detach(HANDLERS)
    if bpy.app.timers.is_registered(_undo_step):
        bpy.app.timers.unregister(_undo_step)
    _undo_wanted.clear()
    _rendering.clear()
