"""Make a BlobTree the one the sidebar works on: select its preview object and make it
active (the sidebar expands the active tree only)."""
import bpy

from .common import context_tree


class BLOBTREE_INK_OT_activate_tree(bpy.types.Operator):
    """Work on this BlobTree: select its preview and make it active"""
    bl_idname = "blobtree_ink.activate_tree"
    bl_label = "Work on BlobTree"
    bl_options = {"REGISTER", "UNDO"}

    tree_name: bpy.props.StringProperty(name="Tree", options={"SKIP_SAVE"}, description="The BlobTree node tree")

    def execute(self, context):
        try:
            tree = context_tree(context, self.tree_name)
        except LookupError as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        obj = tree.preview_object
        if obj is None or obj.name not in context.view_layer.objects:
            self.report({"ERROR"}, f"'{tree.name}' has no preview object in this view layer: switch its Live "
                                   "Preview on")
            return {"CANCELLED"}
        for o in context.view_layer.objects:
            o.select_set(o == obj)
        context.view_layer.objects.active = obj
        return {"FINISHED"}


classes = (BLOBTREE_INK_OT_activate_tree,)
