"""Helpers shared by operators."""
import bpy

from ..blobtree_nodes.tree import TREE, blobtrees, ink_name, tree_of_object  # noqa: F401 (the operators' names for them)


LAYER_TIPS = {
    "Silhouette": "The silhouettes: where the surface turns away from the eye",
    "Crease": "The creases: where unions, intersections and differences meet",
    "Curvature": "Curvature-sign lines: where the surface turns from convex to concave",
    "Suggestive": "Suggestive contours: where the surface comes closest to turning away from the eye",
    "Ridges": "Apparent ridges: the crests where the surface, as seen, bends most sharply",
    "Hatching": "Hatching and cross-hatching in the shade",
    "Chains": "Strokes started from the silhouette and crease chains",
    "Short Strokes": "Short strokes through points spread over the shaded surface",
    "Stipples": "Stipples in the shade",
    "Single Strokes": "The single strokes drawn from the 3D cursor",
}


class InkLayerOperator:
    """Mixin of the operators on one layer of an ink (Grease Pencil) object, which the
    sidebar's Ink Layers rows call with the object's and the layer's names: a subclass
    says what it does (``tip``) and does it to the layer found (``act``)."""
    object_name: bpy.props.StringProperty(name="Ink Object", options={"SKIP_SAVE"},
                                          description="The Grease Pencil object")
    layer: bpy.props.StringProperty(name="Layer", options={"SKIP_SAVE"}, description="The layer")
    tip = ""

    @classmethod
    def description(cls, context, properties):
        return f"{cls.tip}. {LAYER_TIPS.get(properties.layer, f'The {properties.layer} layer')}"

    def execute(self, context):
        obj = bpy.data.objects.get(self.object_name)
        found = obj.data.layers.get(self.layer) if obj is not None and obj.type == "GREASEPENCIL" else None
        if found is None:
            self.report({"ERROR"}, f"no ink layer '{self.layer}' on '{self.object_name}'")
            return {"CANCELLED"}
        return self.act(context, found)


def active_tree(context):
    """The tree the artist is working on: the one in the node editor, else the one whose
    preview or ink object is active, else None."""
    space = getattr(context, "space_data", None)
    if space is not None and getattr(space, "type", "") == "NODE_EDITOR" and space.node_tree is not None \
            and space.node_tree.bl_idname == TREE:
        return space.node_tree
    return tree_of_object(getattr(context, "active_object", None))


_focus = []                   # the name of the tree the artist last worked on (see focus)


def focus(tree=None):
    """Remember ``tree`` as the one the artist works on (the sidebar shows it while no
    BlobTree object is active: its preview may be off); without one, that tree (None
    when it is gone)."""
    if tree is not None:
        _focus[:] = [tree.name]
        return tree
    t = bpy.data.node_groups.get(_focus[0]) if _focus else None
    return t if t is not None and t.bl_idname == TREE else None


def context_tree(context, name=""):
    """The tree named ``name``, else the active one (:func:`active_tree`), else the one
    last worked on (:func:`focus`, as the sidebar shows it), else the only one."""
    if name:
        t = bpy.data.node_groups.get(name)
        if t is None or t.bl_idname != TREE:
            raise LookupError(f"no BlobTree node tree named '{name}'")
        return t
    t = active_tree(context) or focus()
    if t is not None:
        return t
    trees = blobtrees()
    if len(trees) == 1:
        return trees[0]
    if not trees:
        raise LookupError("there is no BlobTree node tree in this file")
    raise LookupError("several BlobTree node trees: select one's preview, open it in a node editor, or name it "
                      "(tree_name)")


def show_in_node_editor(context, tree):
    screen = getattr(context, "screen", None)
    if screen is None:
        return
    for area in screen.areas:
        if area.type == "NODE_EDITOR":
            space = area.spaces.active
            space.tree_type = TREE
            space.node_tree = tree
            return
