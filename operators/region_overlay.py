"""The region of a region request drawn in the 3D viewport while it matters: during a
run of Place Strokes or Find Features (its box or sphere), and, for a tree whose Region
is the sphere around the 3D cursor, all the time (the artist sees where it is while
moving the cursor). Module state keyed by tree name; drawn by a viewport draw handler
in the UI only."""
import bpy
import numpy as np

from .. import pipeline as PL
from ..agents import Region
from ..blobtree_nodes import changes
from ..blobtree_nodes.compile import TreeError, compile_tree
from ..model import Evaluator
from . import jobs
from .common import blobtrees

COLOR = (0.95, 0.45, 0.1, 0.9)      # an orange that reads over the grey grid and the white paper
WIDTH = 2.0
SEGMENTS = 64
_running = {}                        # tree name -> the regions of its run (model coordinates) and the placement
_radius = {}                         # tree name -> (edits, the model's radius), for the cursor sphere
_handle = []


def show(tree_name, regions, placement=None):
    """Draw these regions (agents.Region, in the model's coordinates, placed in the scene
    by ``placement``, a 4x4 matrix) while the tree's run lasts ([]: no more)."""
    if regions:
        _running[tree_name] = (list(regions), np.array(placement if placement is not None else np.eye(4), float))
    else:
        _running.pop(tree_name, None)
    for window in getattr(bpy.context.window_manager, "windows", []):
        for area in window.screen.areas:
            if area.type == "VIEW_3D":
                area.tag_redraw()


def model_radius(tree):
    """The radius of the tree's model (pipeline.bounds), kept until the tree is edited;
    None for a tree that does not compile or has no surface."""
    edits = changes.edits(tree)
    got = _radius.get(tree.name)
    if got is None or got[0] != edits:
        try:
            r = PL.bounds(Evaluator(compile_tree(tree)))[1]
        except (TreeError, PL.NothingToDraw):
            r = None
        got = _radius[tree.name] = (edits, r)
    return got[1]


def outline(region):
    """Line segments ((2k, 3) points) drawing a region: a box's twelve edges, a sphere's
    three great circles."""
    if region.box is not None:
        lo, hi = region.box
        c = np.array([[hi[i] if k >> i & 1 else lo[i] for i in range(3)] for k in range(8)])
        edges = [(a, b) for a in range(8) for b in range(a + 1, 8) if bin(a ^ b).count("1") == 1]
        return np.array([c[i] for e in edges for i in e])
    centre, r = region.sphere
    t = np.linspace(0.0, 2 * np.pi, SEGMENTS + 1)
    ring = np.stack([np.cos(t), np.sin(t), np.zeros_like(t)], axis=1) * r
    out = []
    for perm in ((0, 1, 2), (0, 2, 1), (2, 0, 1)):
        pts = ring[:, perm] + centre
        out.append(np.stack([pts[:-1], pts[1:]], axis=1).reshape(-1, 3))
    return np.concatenate(out)


def segments_now(context):
    """The line segments ((2k, 3) scene points) of every region to draw now."""
    out = []
    for regions, M in _running.values():
        for r in regions:
            P = outline(r)
            out.append(P @ M[:3, :3].T + M[:3, 3])
    for tree in blobtrees():
        if tree.ink.region == "CURSOR" and tree.name not in _running:
            radius = model_radius(tree)
            obj = tree.preview_object
            scale = jobs.scale_of(obj.matrix_world) if obj is not None else 1.0
            if radius is not None:
                out.append(outline(Region(sphere=(np.array(context.scene.cursor.location, float),
                                                  tree.ink.region_size * radius * scale))))
    return out


def _draw():
    import gpu
    from gpu_extras.batch import batch_for_shader
    segments = segments_now(bpy.context)
    if not segments:
        return
    coords = np.concatenate(segments).astype(np.float32)
    shader = gpu.shader.from_builtin("POLYLINE_UNIFORM_COLOR")
    batch = batch_for_shader(shader, "LINES", {"pos": coords})
    gpu.state.blend_set("ALPHA")
    shader.uniform_float("viewportSize", gpu.state.viewport_get()[2:])
    shader.uniform_float("lineWidth", WIDTH)
    shader.uniform_float("color", COLOR)
    batch.draw(shader)
    gpu.state.blend_set("NONE")


def register():
    if not bpy.app.background and not _handle:
        _handle.append(bpy.types.SpaceView3D.draw_handler_add(_draw, (), "WINDOW", "POST_VIEW"))


def unregister():
    while _handle:
        bpy.types.SpaceView3D.draw_handler_remove(_handle.pop(), "WINDOW")
    _running.clear()
    _radius.clear()
