"""Helpers shared by operators."""
import bpy

TREE = "BlobTreeInkNodeTree"


def blobtrees():
    return [t for t in bpy.data.node_groups if t.bl_idname == TREE]


def context_tree(context, name=""):
    """The tree named ``name``, else the one in the active node editor, else the only one."""
    if name:
        t = bpy.data.node_groups.get(name)
        if t is None or t.bl_idname != TREE:
            raise LookupError(f"no BlobTree node tree named '{name}'")
        return t
    space = getattr(context, "space_data", None)
    if space is not None and getattr(space, "type", "") == "NODE_EDITOR" and space.node_tree is not None \
            and space.node_tree.bl_idname == TREE:
        return space.node_tree
    trees = blobtrees()
    if len(trees) == 1:
        return trees[0]
    if not trees:
        raise LookupError("there is no BlobTree node tree in this file")
    raise LookupError("several BlobTree node trees: name one (tree_name) or open it in a node editor")


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
