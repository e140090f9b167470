"""The live preview: a polygonised mesh of the tree's model, rebuilt shortly after
edits stop (debounced with a timer, never on every step of a slider drag), kept in its
own collection, one object per tree.

The pending rebuilds are module state keyed by tree name (not stored on Blender data
or on Python wrappers). A broken tree keeps its previous preview and shows its error
on the offending node.
"""
import contextlib
import time

import bpy

DELAY = 0.35                     # seconds of quiet before a rebuild
COLLECTION = "BlobTree Ink Previews"

_pending = {}                    # tree name -> monotonic time the rebuild is due
_edits = {}                      # tree name -> number of edits seen (a running illustration stops on change)
stats = {"rebuilds": 0}          # for tests and the UI


def edits(tree):
    return _edits.get(tree.name, 0)


_held = []                       # trees whose edits are being gathered (see hold)


@contextlib.contextmanager
def hold():
    """Gather edits (e.g. the thousands an importer makes) and schedule each tree's
    preview once at the end, instead of once per property write."""
    _held.append(set())
    try:
        yield
    finally:
        names = _held.pop()
        for name in names:
            tree = bpy.data.node_groups.get(name)
            if tree is not None:
                schedule(tree)


def schedule(tree, delay=DELAY):
    if _held:
        _held[-1].add(tree.name)
        return
    _edits[tree.name] = _edits.get(tree.name, 0) + 1
    _pending[tree.name] = time.monotonic() + delay
    if not bpy.app.timers.is_registered(_tick):
        bpy.app.timers.register(_tick, first_interval=delay)


def pending():
    return dict(_pending)


def _tick():
    now = time.monotonic()
    run_due(now)
    if not _pending:
        return None
    return max(0.02, min(_pending.values()) - now)


def run_due(now=None):
    """Rebuild every preview whose quiet period is over; returns the trees rebuilt."""
    now = time.monotonic() if now is None else now
    done = []
    for name, due in list(_pending.items()):
        if due > now:
            continue
        del _pending[name]
        tree = bpy.data.node_groups.get(name)
        if tree is not None and tree.bl_idname == "BlobTreeInkNodeTree":
            if rebuild(tree):
                done.append(name)
    return done


def rebuild(tree):
    """Polygonise the tree's model into its preview object. False for a broken tree
    (the old preview stays) or when the preview is switched off (it is removed)."""
    from ..blackboard.polygonise import GridError, polygonise
    from ..model import Evaluator
    from .compile import tree_model_or_none
    if not tree.show_preview:
        remove(tree)
        return False
    model = tree_model_or_none(tree)
    if model is None:
        return False
    try:
        mesh = polygonise(Evaluator(model), int(tree.preview_resolution))
    except GridError as e:
        _output_error(tree, str(e))
        return False
    obj = _preview_object(tree)
    write_mesh(obj.data, mesh.vertices, mesh.quads)
    stats["rebuilds"] += 1
    return True


def _output_error(tree, message):
    for n in tree.nodes:
        if n.bl_idname == "BlobTreeInkOutputNode":
            n.set_error(message)


def _collection():
    coll = bpy.data.collections.get(COLLECTION)
    if coll is None:
        coll = bpy.data.collections.new(COLLECTION)
    scene = bpy.context.scene
    if scene is not None and coll.name not in scene.collection.children:
        scene.collection.children.link(coll)
    return coll


def _preview_object(tree):
    obj = tree.preview_object
    if obj is not None and obj.name in bpy.data.objects and obj.type == "MESH":
        if not obj.users_collection:
            _collection().objects.link(obj)
        return obj
    me = bpy.data.meshes.new(f"{tree.name} Preview")
    obj = bpy.data.objects.new(f"{tree.name} Preview", me)
    _collection().objects.link(obj)
    tree.preview_object = obj
    return obj


def remove(tree):
    obj = tree.preview_object
    if obj is not None:
        me = obj.data
        bpy.data.objects.remove(obj)
        if me is not None and me.users == 0:
            bpy.data.meshes.remove(me)
        tree.preview_object = None


def write_mesh(me, vertices, quads):
    """Replace a mesh's geometry with quads in bulk (foreach_set, no Python loops)."""
    import numpy as np
    me.clear_geometry()
    nv, nf = len(vertices), len(quads)
    me.vertices.add(nv)
    me.vertices.foreach_set("co", np.asarray(vertices, np.float32).ravel())
    me.loops.add(4 * nf)
    me.loops.foreach_set("vertex_index", np.asarray(quads, np.int32).ravel())
    me.polygons.add(nf)
    me.polygons.foreach_set("loop_start", np.arange(0, 4 * nf, 4, dtype=np.int32))
    me.update()
    return me


@bpy.app.handlers.persistent
def _after_undo(*_args):
    for tree in bpy.data.node_groups:
        if tree.bl_idname == "BlobTreeInkNodeTree" and tree.show_preview:
            schedule(tree)


@bpy.app.handlers.persistent
def _after_load(*_args):
    # another file: its trees may have the names of the old file's trees
    _pending.clear()
    _edits.clear()


HANDLERS = ((bpy.app.handlers.undo_post, _after_undo), (bpy.app.handlers.redo_post, _after_undo),
            (bpy.app.handlers.load_post, _after_load))


def register():
    for lst, fn in HANDLERS:
        if fn not in lst:
            lst.append(fn)


def unregister():
    for lst, fn in HANDLERS:
        if fn in lst:
            lst.remove(fn)
    if bpy.app.timers.is_registered(_tick):
        bpy.app.timers.unregister(_tick)
    _pending.clear()
