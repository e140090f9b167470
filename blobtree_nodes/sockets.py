"""The field socket that connects BlobTree nodes."""
import bpy

SOCKET = "BlobTreeInkFieldSocket"


class BlobTreeFieldSocket(bpy.types.NodeSocket):
    """A scalar field: a primitive, or operators and warps over primitives"""
    bl_idname = SOCKET
    bl_label = "Field"

    def draw(self, context, layout, node, text):
        layout.label(text=text)

    def draw_color(self, context, node):
        return (0.35, 0.75, 0.95, 1.0)


classes = (BlobTreeFieldSocket,)
