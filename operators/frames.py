"""A tree illustrated at a frame, for the bake, the render handler and the command
line's frames: the tree compiled as it is then (its animation, its followed objects),
seen by the scene's camera and lit by its lights then, its requests the tree's look
(the outlines and the style's strokes); the result written as that frame's drawing.
The frames a render drew are listed on the ink object: a later render draws them
again unless they were made from all that frame's job is made from, for its eye (:func:`holds`),
while frames drawn otherwise (baked, or drawn by the artist at that frame) are kept."""
import bpy

from .. import pipeline as PL
from ..blobtree_nodes import preview
from ..blobtree_nodes.base import shown_name
from ..blobtree_nodes.animation import DriverError
from ..blobtree_nodes.compile import TreeError, compile_tree, in_no_scene, show_outcome
from ..blobtree_nodes.settings import style_of
from ..grease_pencil import views
from ..grease_pencil.writer import ink_object, write
from ..pipeline.job import SINGLE_LAYER
from ..strokes.data import LAYER_OF_KIND, LAYERS
from . import jobs
from .common import ink_name

RENDERED = "blobtree_ink_rendered"    # the ink object's custom property: the frames a render drew


class FrameError(ValueError):
    """A frame that cannot be illustrated; the message names the frame and what is wrong."""


def look_requests(tree):
    """The requests of a frame: the outlines, and the style's strokes when it has any."""
    requests = [PL.Request(PL.OUTLINES)]
    if style_of(tree.ink).stroke_switches():
        requests.append(PL.Request(PL.PLACE_STROKES))
    return tuple(requests)


class Compiled:
    """The trees of one frame, each compiled once as ``depsgraph`` evaluates them: a
    frame of a render draws every tree, each hidden by the others."""

    def __init__(self, depsgraph=None):
        self.depsgraph = depsgraph
        self._got = {}             # tree name -> its Model, or the TreeError or DriverError compiling it raised

    def model(self, tree, mark=True):
        """compile_tree's Model of the tree; ``mark``: show the outcome on its nodes."""
        got = self._got.get(tree.name)
        if got is None:
            try:
                got = compile_tree(tree, mark=False, depsgraph=self.depsgraph)
            except (TreeError, DriverError) as e:
                got = e
            self._got[tree.name] = got
        if mark and not isinstance(got, DriverError):
            show_outcome(tree, got if isinstance(got, TreeError) else None)
        if isinstance(got, Exception):
            raise got
        return got


def frame_job(tree, scene, depsgraph=None, compiled=None):
    """The job of the scene's current frame (the scene's other models hiding its lines;
    the console names those whose trees do not compile), and the placement of the model
    then; ``compiled``: the frame's trees compiled so far (:class:`Compiled`)."""
    compiled = compiled if compiled is not None else Compiled(depsgraph)
    model = compiled.model(tree)
    place = jobs.placement(tree, depsgraph)
    ink = tree.ink
    solids, broken = jobs.occluders(scene, tree, depsgraph, compiled.model)
    if broken:
        print(f"BlobTree Ink: frame {scene.frame_current} of '{tree.name}': {jobs.hidden_by_note(broken)}")
    job = jobs.job(model, scene, style_of(ink), jobs.tree_settings(ink), look_requests(tree), ink.seed,
                   inverse=place.inverted_safe(), depsgraph=depsgraph, occluders=solids)
    return job, place


def holds(tree, job, frame):
    """Whether the tree's ink shows on ``frame`` (held from an earlier key if need be)
    a drawing of every layer the frame's ``job`` draws, made from all the job is made
    from (its model, light, style, seed and settings) for its very eye: a render can use
    it as it is. A job with no eye of its own (no scene camera) is never taken as held."""
    obj = bpy.data.objects.get(ink_name(tree))
    if obj is None or job.view is None:
        return False
    checked = job.checked()
    return views.holds(obj, checked.owned_layers(), frame, job.view.eye, checked.making(jobs.model_key(job)))


def write_frame(tree, result, frame, rendered=False):
    """Write a frame's result as that frame's drawing of the tree's ink; ``rendered``:
    list the frame as drawn by a render."""
    obj = ink_object(ink_name(tree), preview.tree_collection(tree))
    jobs.attach(obj, tree)
    write(obj, result, frame=frame)
    frames = set(obj.get(RENDERED, []))
    frames.add(frame) if rendered else frames.discard(frame)
    obj[RENDERED] = sorted(frames)
    return obj


def shown_counts(obj, frame):
    """{layer: the strokes of its drawing shown at ``frame``} of a Grease Pencil object
    (0 before a layer's first key)."""
    return {layer.name: strokes_at(layer, frame) for layer in obj.data.layers}


def strokes_at(layer, frame):
    """The strokes of a layer's drawing shown at a frame (0 before its first key)."""
    key = views.shown_frame(layer, frame)
    return len(key.drawing.strokes) if key is not None else 0


DRAWN = tuple(n for n in LAYERS if n != SINGLE_LAYER)     # the layers the extension draws (not the artist)


def end_hold(obj, frame, until=None, layers=None):
    """Grease Pencil holds a layer's drawing until the layer's next key: each layer (of
    ``layers``, default all) that shows strokes at ``frame`` and has no key after it up
    to ``until`` (default the next frame) gets an empty drawing at ``until``, so the
    frames after a bake's range, or a cleared range, show no ink instead of a drawing
    held over a model that moved on (a render still draws them: an empty drawing is no
    drawn frame). Returns the layers that got one."""
    until = frame + 1 if until is None else until
    ended = []
    for layer in obj.data.layers:
        if layers is not None and layer.name not in layers:
            continue
        shown = views.shown_frame(layer, frame)
        if shown is not None and len(shown.drawing.strokes) and \
                all(not frame < f.frame_number <= until for f in layer.frames):
            layer.frames.new(until)
            ended.append(layer.name)
    return ended


def hold_to_next(obj, layers, frame):
    """After ``layers`` were drawn on ``frame`` of an ink that has drawings on later frames
    (a bake's): each that has no key of its own up to the ink's next key of a drawn
    layer gets an empty drawing there (:func:`end_hold`), so it does not show over the
    later frames' own drawings (the artist's single strokes, and layers not the
    extension's, do not count). Returns the frames after ``frame`` that have a drawing
    of their own."""
    later = sorted({f.frame_number for layer in obj.data.layers if layer.name in DRAWN
                    for f in layer.frames if f.frame_number > frame})
    if later:
        end_hold(obj, frame, later[0], layers)
    return [f for f in drawn_frames_of(obj) if f > frame]


def drawn_frames(tree):
    """The frames the tree's ink has a drawing of (a key on its outline layers)."""
    return drawn_frames_of(bpy.data.objects.get(ink_name(tree)))


def drawn_frames_of(obj):
    """The frames an ink object has a drawing of (a key with strokes on its outline layers)."""
    if obj is None or obj.type != "GREASEPENCIL":
        return set()
    return {f.frame_number for layer in obj.data.layers if layer.name in LAYER_OF_KIND.values()
            for f in layer.frames if len(f.drawing.strokes)}


def clear_frames(obj, frames):
    """Remove an ink object's drawings at ``frames`` (a range) on every layer, the frames
    then showing no ink (:func:`end_hold`); returns the frames that had one."""
    gone = set()
    for layer in obj.data.layers:
        for f in [f.frame_number for f in layer.frames if f.frame_number in frames]:
            layer.frames.remove(f)
            gone.add(f)
    obj[RENDERED] = sorted(set(obj.get(RENDERED, [])) - frames)
    if gone:                           # the cleared frames show no ink, not the drawing before them
        end_hold(obj, min(frames) - 1)
    return gone


def spans(frames):
    """Frames as short text: "1-24, 30, 40-45"."""
    out, run = [], []
    for f in sorted(frames):
        if run and f == run[-1] + 1:
            run.append(f)
            continue
        if run:
            out.append(f"{run[0]}-{run[-1]}" if len(run) > 1 else str(run[0]))
        run = [f]
    if run:
        out.append(f"{run[0]}-{run[-1]}" if len(run) > 1 else str(run[0]))
    return ", ".join(out)


def rendered_frames(tree):
    obj = bpy.data.objects.get(ink_name(tree))
    return set(obj.get(RENDERED, [])) if obj is not None else set()


def followed_objects(tree):
    """(node name, property, object name) of every object the tree's nodes follow."""
    out = []
    for node in tree.nodes:
        for key in node.bl_rna.properties.keys():
            obj = getattr(node, key, None) if key.endswith("object") else None
            if isinstance(obj, bpy.types.Object):
                out.append((node.name, key, obj.name))
    return out


def check_followed(tree, followed, frame):
    """FrameError when an object the tree followed at the start is gone: removed, or
    deleted in the viewport (an object a node still points to stays in bpy.data, in no
    scene, and its animation is no longer evaluated: blobtree_nodes.compile says so too)."""
    for node_name, key, obj_name in followed:
        node = tree.nodes.get(node_name)
        obj = None if node is None else getattr(node, key, None)
        if obj is None or in_no_scene(obj):
            label = node_name if node is None else shown_name(node)
            raise FrameError(f"frame {frame}: the object '{obj_name}' that node '{label}' follows was "
                             "deleted")


def frame_range(start, end):
    """The frames from start to end (both included); FrameError for an empty or
    reversed range."""
    if end < start:
        raise FrameError(f"the frame range {start}-{end} is empty (it ends before it starts)")
    return range(start, end + 1)
