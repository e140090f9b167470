"""The BlobTree node editor (Blender layer): tree, nodes, compiler, preview, menus."""
import bpy

from . import menu, nodes, preview, settings, sockets, tree

classes = (*settings.classes, *sockets.classes, *tree.classes, *nodes.classes)


def register():
    for c in classes:
        bpy.utils.register_class(c)
    menu.register()
    preview.register()


def unregister():
    preview.unregister()
    menu.unregister()
    for c in reversed(classes):
        bpy.utils.unregister_class(c)
