"""The BlobTree Ink menu of the 3D viewport's Object menu: the requests and the looks,
so that they are in menu search (F3) as well as in the sidebar."""
import bpy

from ..blobtree_nodes.settings import PRESETS
from .illustrate import REQUESTS

REQUEST_ICONS = {"OUTLINES": "MOD_LINEART", "SINGLE_STROKE": "GREASEPENCIL", "PLACE_STROKES": "BRUSH_DATA",
                 "FIND_FEATURES": "VIEWZOOM"}


class VIEW3D_MT_blobtree_ink_looks(bpy.types.Menu):
    """Set the active BlobTree's style to a look and draw it"""
    bl_label = "Looks"
    bl_idname = "VIEW3D_MT_blobtree_ink_looks"

    def draw(self, context):
        for key in PRESETS:
            op = self.layout.operator("blobtree_ink.illustrate", text=key.replace("_", " ").title())
            op.preset, op.request = key, "PLACE_STROKES"


class VIEW3D_MT_blobtree_ink(bpy.types.Menu):
    """Illustrate the active BlobTree in pen and ink"""
    bl_label = "BlobTree Ink"
    bl_idname = "VIEW3D_MT_blobtree_ink"

    def draw(self, context):
        layout = self.layout
        for ident, label, _ in REQUESTS:
            layout.operator("blobtree_ink.illustrate", text=label, icon=REQUEST_ICONS[ident]).request = ident
        layout.menu(VIEW3D_MT_blobtree_ink_looks.bl_idname)
        layout.separator()
        layout.operator("blobtree_ink.bake", text="Bake Frames", icon="RENDER_ANIMATION")
        layout.operator("blobtree_ink.clear_frames", text="Clear Frames", icon="TRASH")
        layout.separator()
        layout.operator("blobtree_ink.import_json", icon="IMPORT")


def object_menu(self, context):
    self.layout.separator()
    self.layout.menu(VIEW3D_MT_blobtree_ink.bl_idname)


classes = (VIEW3D_MT_blobtree_ink_looks, VIEW3D_MT_blobtree_ink)


def register():
    bpy.types.VIEW3D_MT_object.append(object_menu)


def unregister():
    bpy.types.VIEW3D_MT_object.remove(object_menu)
