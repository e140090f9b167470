"""Models that move: on every frame change (in the UI, a bake, a render) each tree's
animation is written at the new frame (blobtree_nodes.animation) and the trees that
changed, or that follow objects, have their preview rebuilt (debounced, as edits are);
when an object a tree follows moves (the artist drags it, a constraint), so does the
tree's preview. A tree's followed objects are kept per tree until it is edited."""
import bpy

from . import animation, changes, handlers
from .compile import in_no_scene
from .idnames import TREE

_followed = {}                   # tree name -> (edit count, names of the objects its nodes follow)
_gone = {}                       # tree name -> those of them in no scene, as last seen


def trees():
    return [t for t in bpy.data.node_groups if t.bl_idname == TREE]


def followed(tree):
    """Names of the objects the tree's nodes follow."""
    edits = changes.edits(tree)
    got = _followed.get(tree.name)
    if got is None or got[0] != edits:
        names = set()
        for node in tree.nodes:
            for key in node.bl_rna.properties.keys():
                if key.endswith("object") and isinstance(getattr(node, key, None), bpy.types.Object):
                    names.add(getattr(node, key).name)
        got = _followed[tree.name] = (edits, names)
    return got[1]


def frame_of(scene):
    return scene.frame_current + scene.frame_subframe


def follow_frame(scene, depsgraph=None):
    """Write every tree's animation at the scene's frame; schedule the previews of the
    trees that changed or follow objects. Returns the trees that may have moved."""
    moved = []
    for tree in trees():
        with changes.moving():
            changed = animation.apply(tree, frame_of(scene), depsgraph)
        if changed or followed(tree):
            moved.append(tree)
            if tree.show_preview:
                changes.schedule(tree, edit=False)
    return moved


@bpy.app.handlers.persistent
def _frame_changed(scene, depsgraph=None):
    follow_frame(scene, depsgraph)


def _now_gone(names):
    """Which of these followed objects are in no scene (or no longer exist)."""
    return frozenset(n for n in names if (o := bpy.data.objects.get(n)) is None or in_no_scene(o))


@bpy.app.handlers.persistent
def _depsgraph_updated(scene, depsgraph):
    """A followed object moved: its trees' previews follow. A followed object left every
    scene or came back (deleted in the viewport, brought back by undo): its trees are
    compiled again (a node following one in no scene says so). A collection or scene
    update that changes neither (a selection, a setting) rebuilds nothing."""
    moved = {u.id.original.name for u in depsgraph.updates
             if isinstance(u.id, bpy.types.Object) and u.is_updated_transform}
    regrouped = any(isinstance(u.id, (bpy.types.Collection, bpy.types.Scene)) for u in depsgraph.updates)
    if not moved and not regrouped:
        return
    for tree in trees():
        names = followed(tree)
        if not names:
            continue
        gone = _now_gone(names) if regrouped else _gone.get(tree.name, frozenset())
        came_or_went = gone != _gone.get(tree.name, frozenset())
        _gone[tree.name] = gone
        if tree.show_preview and (moved & names or came_or_went):
            changes.schedule(tree, edit=False)


@bpy.app.handlers.persistent
def _loaded(*_args):
    _followed.clear()
    _gone.clear()
    scene = bpy.context.scene
    if scene is not None:
        for tree in trees():
            with changes.moving():
                animation.apply(tree, frame_of(scene))


HANDLERS = ((bpy.app.handlers.frame_change_post, _frame_changed),
            (bpy.app.handlers.depsgraph_update_post, _depsgraph_updated),
            (bpy.app.handlers.load_post, _loaded))


def register():
    handlers.attach(HANDLERS)


def unregister():
    handlers.detach(HANDLERS)
    _followed.clear()
