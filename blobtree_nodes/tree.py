"""The BlobTree node tree type and its settings; which tree an object belongs to, and
which tree a node editor shows."""
import bpy

from . import changes
from .idnames import TREE
from .settings import BlobTreeInkSettings


def _schedule(tree):
    changes.schedule(tree)


def blobtrees():
    return [t for t in bpy.data.node_groups if t.bl_idname == TREE]


def ink_name(tree):
    """The name of a tree's ink (Grease Pencil) object."""
    return f"{tree.model_name or tree.name} Ink"


def tree_of_object(obj):
    """The BlobTree whose preview or ink object this is, or None."""
    if obj is None:
        return None
    for t in blobtrees():
        if t.preview_object is not None and t.preview_object.name == obj.name:
            return t
        if obj.name == ink_name(t):
            return t
    return None


_followed = {}                   # a node editor's address -> the active object it last followed


def shown_in_editor(space, obj):
    """The tree a BlobTree node editor (``space``, not pinned) shows while ``obj`` is the
    active object: that object's tree when the artist has made another object active
    since the editor last looked (or the editor shows none), else the tree the editor
    shows (one the artist browsed to, or the one a file was saved with)."""
    key = space.as_pointer() if space is not None else 0
    name = obj.name_full if obj is not None else ""
    shown = getattr(space, "node_tree", None)
    shown = shown if shown is not None and shown.bl_idname == TREE else None
    moved = key in _followed and _followed[key] != name
    _followed[key] = name
    owned = tree_of_object(obj)
    return owned if owned is not None and (moved or shown is None) else shown


class BlobTreeNodeTree(bpy.types.NodeTree):
    """A skeletal implicit model built from BlobTree nodes"""
    bl_idname = TREE
    bl_label = "BlobTree"
    bl_icon = "META_BALL"
    bl_use_group_interface = False      # a model has no sockets of its own, nor groups: no Group Sockets panel

    iso: bpy.props.FloatProperty(name="Iso Value", default=0.5, soft_min=0.01, soft_max=2.0,
                                 description="The surface is where the field equals this value",
                                 update=lambda self, ctx: _schedule(self))
    preview_resolution: bpy.props.IntProperty(name="Preview Resolution", default=32, min=8, max=128,
                                              description="About Resolution^3 cubic cells over the model for the preview mesh",
                                              update=lambda self, ctx: _schedule(self))
    show_preview: bpy.props.BoolProperty(name="Live Preview", default=True,
                                         description="Keep a polygonised preview mesh of the model up to date",
                                         update=lambda self, ctx: _schedule(self))
    preview_object: bpy.props.PointerProperty(type=bpy.types.Object, name="Preview Object",
                                              description="The polygonised preview mesh of the model")
    collection: bpy.props.PointerProperty(type=bpy.types.Collection, name="Collection",
                                          description="The collection of the tree's preview and ink objects")
    model_name: bpy.props.StringProperty(name="Model Name", description="The model's name in exported JSON "
                                         "(the tree's name when empty)")
    exact_iso: bpy.props.StringProperty(options={"HIDDEN"})
    ink: bpy.props.PointerProperty(type=BlobTreeInkSettings, name="Illustration Settings")

    @classmethod
    def get_from_context(cls, context):
        """The editor follows the active object's tree, as a shader editor follows its
        material; the pin keeps a tree."""
        space = getattr(context, "space_data", None)
        if space is None or getattr(space, "type", "") != "NODE_EDITOR":
            return None, None, None
        return shown_in_editor(space, getattr(context, "active_object", None)), None, None

    def update(self):
        # a tree is nobody's data-block user: keep it in saved files like a material
        if not self.use_fake_user:
            self.use_fake_user = True
        _schedule(self)


classes = (BlobTreeNodeTree,)
