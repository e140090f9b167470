"""The BlobTree node editor (Blender layer)."""
import bpy

from . import tree

classes = (*tree.classes,)


def register():
    for c in classes:
        bpy.utils.register_class(c)


def unregister():
    for c in reversed(classes):
        bpy.utils.unregister_class(c)
