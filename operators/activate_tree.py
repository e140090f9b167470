"""Make a BlobTree the one the sidebar works on: select its preview object (else its
ink object) and make it active; with neither (its preview off, nothing drawn) the
sidebar shows it as the tree last worked on (common.focus)."""
import bpy

from .common import context_tree, focus, ink_name


class BLOBTREE_INK_OT_activate_tree(bpy.types.Operator):
    """Work on this BlobTree: show it in the sidebar, its preview (or ink) selected and active"""
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
        focus(tree)
        objects = context.view_layer.objects
        obj = next((o for o in (tree.preview_object, bpy.data.objects.get(ink_name(tree)))
                    if o is not None and o.name in objects), None)
        for o in objects:
            if o.select_get() != (o == obj):
                o.select_set(o == obj)
        objects.active = obj           # none (its preview off, nothing drawn): the sidebar shows it all the same
        return {"FINISHED"}


classes = (BLOBTREE_INK_OT_activate_tree,)
