"""The live preview: a polygonised mesh of the tree's model, rebuilt shortly after
edits stop (blobtree_nodes.changes debounces them). Each tree has a collection of its
own (inside the BlobTree Ink collection) that holds its preview object and its ink
(Grease Pencil) object. The preview is left out of renders unless the tree's Render
Preview Mesh is on, and is white while the tree's Paper is on. A broken tree keeps its
previous preview and shows its error on the offending node.
"""
import bpy
import numpy as np

from mathutils import Vector

from ..blackboard.polygonise import GridError, polygonise, surface_box
from ..model import Evaluator, fingerprint
from . import changes, handlers
from .compile import tree_model_or_none
from .idnames import TREE

COLLECTION = "BlobTree Ink"
PAPER_MATERIAL = "BlobTree Ink Paper Mesh"
stats = {"rebuilds": 0}          # for tests and the UI
SHOWN_MODEL = "blobtree_ink_model"    # the preview object's ID property: the key (model.fingerprint) of the model
                                      # it shows


def rebuild(tree):
    """Polygonise the tree's model into its preview object. False for a broken tree
    (the old preview stays) or when the preview is switched off (it is removed)."""
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
    paper_look(tree)
    obj[SHOWN_MODEL] = fingerprint(model)
    stats["rebuilds"] += 1
    return True


def shown_model(tree):
    """The key (model.fingerprint) of the model the tree's preview shows, or None (no
    preview)."""
    obj = tree.preview_object if tree.show_preview else None
    return None if obj is None else obj.get(SHOWN_MODEL)


def paper_look(tree):
    """The preview mesh in white while the tree's Paper is on (ink reads on it in the
    viewport), with no material of its own otherwise."""
    obj = tree.preview_object
    if obj is None or obj.data is None:
        return
    mats = obj.data.materials
    if tree.ink.paper:
        mat = bpy.data.materials.get(PAPER_MATERIAL) or bpy.data.materials.new(PAPER_MATERIAL)
        mat.diffuse_color = (1.0, 1.0, 1.0, 1.0)
        mat.roughness = 1.0
        if len(mats) != 1 or mats[0] != mat:
            mats.clear()
            mats.append(mat)
    elif len(mats) and mats[0] is not None and mats[0].name == PAPER_MATERIAL:
        mats.clear()


def _output_error(tree, message):
    for n in tree.nodes:
        if n.bl_idname == "BlobTreeInkOutputNode":
            n.set_error(message)


def _parent_collection():
    coll = bpy.data.collections.get(COLLECTION)
    if coll is None:
        coll = bpy.data.collections.new(COLLECTION)
    scene = bpy.context.scene
    if scene is not None and coll.name not in scene.collection.children:
        scene.collection.children.link(coll)
    return coll


def tree_collection(tree):
    """The tree's own collection (its preview and its ink), made on first use."""
    coll = tree.collection
    parent = _parent_collection()
    if coll is None or coll.name not in bpy.data.collections:
        coll = bpy.data.collections.new(tree.name)
        tree.collection = coll
    if coll.name not in parent.children:
        parent.children.link(coll)
    return coll


def _preview_object(tree):
    obj = tree.preview_object
    if obj is not None and obj.name in bpy.data.objects and obj.type == "MESH":
        if not obj.users_collection:
            tree_collection(tree).objects.link(obj)
        return obj
    me = bpy.data.meshes.new(f"{tree.name} Preview")
    obj = bpy.data.objects.new(f"{tree.name} Preview", me)
    obj.hide_render = not tree.ink.render_preview
    tree_collection(tree).objects.link(obj)
    tree.preview_object = obj
    return obj


GAP = 0.25                       # between placed models, as a fraction of the larger one's size


def place_beside(tree, model):
    """Make the tree's preview object (its model's placement in the scene) and put it
    beside the other BlobTrees' previews along +x, not on top of them. Returns it."""
    box = surface_box(Evaluator(model))
    obj = _preview_object(tree)
    if box is None:
        return obj
    lo, hi = box
    right, size = None, float(np.max(hi - lo))
    for other in bpy.data.node_groups:
        o = getattr(other, "preview_object", None) if other != tree else None
        if o is None or o.name not in bpy.data.objects or not len(o.data.vertices):
            continue
        corners = np.array([o.matrix_world @ Vector(c) for c in o.bound_box])
        right = corners[:, 0].max() if right is None else max(right, corners[:, 0].max())
        size = max(size, float(np.ptp(corners, axis=0).max()))
    if right is not None:
        obj.location = (right + GAP * size - lo[0], 0.0, 0.0)
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
        if tree.bl_idname == TREE and tree.show_preview:
            changes.schedule(tree)


@bpy.app.handlers.persistent
def _after_load(*_args):
    """A file's previews as it saved them; one saved while its preview was still being
    built (the mesh comes a moment after an import or an edit in the UI) has an empty
    mesh, and is built again."""
    changes.forget()
    for tree in bpy.data.node_groups:
        if tree.bl_idname == TREE and tree.show_preview:
            obj = tree.preview_object
            if obj is not None and obj.data is not None and len(obj.data.vertices) == 0:
                changes.schedule(tree, edit=False)


HANDLERS = ((bpy.app.handlers.undo_post, _after_undo), (bpy.app.handlers.redo_post, _after_undo),
            (bpy.app.handlers.load_post, _after_load))


def register():
    changes.on_due(rebuild)
    handlers.attach(HANDLERS)


def unregister():
    handlers.detach(HANDLERS)
    changes.stop()
    changes.on_due(None)
