"""The BlobTree node tree type."""
import bpy


class BlobTreeNodeTree(bpy.types.NodeTree):
    """A skeletal implicit model built from BlobTree nodes"""
    bl_idname = "BlobTreeInkNodeTree"
    bl_label = "BlobTree"
    bl_icon = "META_BALL"


classes = (BlobTreeNodeTree,)
