"""The BlobTree node tree type and its settings."""
import bpy

from . import changes
from .settings import BlobTreeInkSettings

def _schedule(tree):
    changes.schedule(tree)


class BlobTreeNodeTree(bpy.types.NodeTree):
    """A skeletal implicit model built from BlobTree nodes"""
    bl_idname = "BlobTreeInkNodeTree"
    bl_label = "BlobTree"
    bl_icon = "META_BALL"

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

    def update(self):
        # a tree is nobody's data-block user: keep it in saved files like a material
        if not self.use_fake_user:
            self.use_fake_user = True
        _schedule(self)


classes = (BlobTreeNodeTree,)
