"""Clear the drawings a tree's ink has in a range of frames (a bake's, a render's, or
the artist's), on every layer, as one undo step."""
import bpy

from ..blobtree_nodes.settings import bake_range
from . import frames as FR
from .common import context_tree, ink_name


class BLOBTREE_INK_OT_clear_frames(bpy.types.Operator):
    """Remove the ink's drawings in a range of frames (by default the tree's bake range)"""
    bl_idname = "blobtree_ink.clear_frames"
    bl_label = "Clear BlobTree Ink Frames"
    bl_options = {"REGISTER", "UNDO"}

    tree_name: bpy.props.StringProperty(name="Tree", options={"SKIP_SAVE"},
                                        description="The BlobTree node tree (empty: the active one)")
    frame_start: bpy.props.IntProperty(name="Start", default=1, options={"SKIP_SAVE"},
                                       description="First frame to clear (unset: the tree's bake range)")
    frame_end: bpy.props.IntProperty(name="End", default=250, options={"SKIP_SAVE"},
                                     description="Last frame to clear (unset: the tree's bake range)")

    def execute(self, context):
        try:
            tree = context_tree(context, self.tree_name)
            start, end = bake_range(tree.ink, context.scene)
            if self.properties.is_property_set("frame_start"):
                start = self.frame_start
            if self.properties.is_property_set("frame_end"):
                end = self.frame_end
            frames = set(FR.frame_range(start, end))
        except (LookupError, FR.FrameError) as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        obj = bpy.data.objects.get(ink_name(tree))
        gone = FR.clear_frames(obj, frames) if obj is not None and obj.type == "GREASEPENCIL" else set()
        self.report({"INFO"}, f"cleared {len(gone)} frame{'s' if len(gone) != 1 else ''} of '{tree.name}'"
                    if gone else f"'{tree.name}' has no drawing in frames {start}-{end}")
        return {"FINISHED"}


classes = (BLOBTREE_INK_OT_clear_frames,)
