"""The BlobTree node editor (Blender layer): tree, nodes, compiler, preview, menus,
the sidebar's Errors panel."""
import bpy

from . import follow, menu, nodes, panels, preview, settings, show_node_error, sockets, tree

classes = (*settings.classes, *sockets.classes, *tree.classes, *nodes.classes, *show_node_error.classes,
           *panels.classes)


def register():
    for c in classes:
        bpy.utils.register_class(c)
    menu.register()
    preview.register()
    follow.register()


def unregister():
    follow.unregister()
    preview.unregister()
    menu.unregister()
    for c in reversed(classes):
        bpy.utils.unregister_class(c)
