"""Operators (Blender layer), one per file, and the sidebar panels."""
import bpy

from . import (activate_tree, apply_preset, bake, clear_frames, clear_layer, export_json, frame_camera, illustrate,
               import_json, menus, panels, rebuild_preview, region_overlay, render_frames, toggle_layer, undo_guard)

classes = (*import_json.classes, *export_json.classes, *rebuild_preview.classes, *illustrate.classes,
           *apply_preset.classes, *toggle_layer.classes, *clear_layer.classes, *activate_tree.classes, *bake.classes,
           *clear_frames.classes, *frame_camera.classes, *panels.classes,
           *menus.classes)


def register():
    for c in classes:
        bpy.utils.register_class(c)
    bpy.types.TOPBAR_MT_file_import.append(import_json.menu_func)
    bpy.types.TOPBAR_MT_file_export.append(export_json.menu_func)
    region_overlay.register()
    menus.register()
    render_frames.register()
    undo_guard.register()


def unregister():
    undo_guard.unregister()
    render_frames.unregister()
    menus.unregister()
    region_overlay.unregister()
    bpy.types.TOPBAR_MT_file_export.remove(export_json.menu_func)
    bpy.types.TOPBAR_MT_file_import.remove(import_json.menu_func)
    for c in reversed(classes):
        bpy.utils.unregister_class(c)
