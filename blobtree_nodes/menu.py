"""The BlobTree node editor's Add menu (Shift+A): Primitives, Operators, Warps and
Output as menus inside Blender's Add menu, which searches them as soon as one types;
each item's tooltip is its node type's description."""
import bpy

from ..model import nodes as N
from .base import in_blobtree_editor
from .nodes import BY_KIND, BlobTreeOutputNode, idname

SUBMENUS = (("Primitives", tuple(idname(k) for k in N.PRIMITIVES)),
            ("Operators", tuple(idname(k) for k in N.OPERATORS)),
            ("Warps", tuple(idname(k) for k in N.UNARY)),
            ("Output", (BlobTreeOutputNode.bl_idname,)))
NODE_CLASSES = {c.bl_idname: c for c in BY_KIND.values()}


def add_node_item(layout, node_idname):
    """An Add menu item: Blender's own Add Node operator, the node following the mouse."""
    cls = NODE_CLASSES[node_idname]
    props = layout.operator("node.add_node", text=cls.bl_label, icon=cls.bl_icon)
    props.type = node_idname
    props.use_transform = True
    return props


class _AddSubmenu:
    bl_space_type = "NODE_EDITOR"
    node_idnames = ()

    @classmethod
    def poll(cls, context):
        return in_blobtree_editor(context)

    def draw(self, context):
        for name in self.node_idnames:
            add_node_item(self.layout, name)


def _submenu(label, node_idnames):
    ident = f"NODE_MT_blobtree_ink_{label.lower()}"
    return type(ident, (_AddSubmenu, bpy.types.Menu),
                {"bl_idname": ident, "bl_label": label, "node_idnames": node_idnames})


SUBMENU_CLASSES = tuple(_submenu(label, names) for label, names in SUBMENUS)


class NODE_MT_blobtree_ink_add(bpy.types.Menu):
    bl_idname = "NODE_MT_blobtree_ink_add"
    bl_label = "Add"
    bl_space_type = "NODE_EDITOR"
    bl_options = {"SEARCH_ON_KEY_PRESS"}

    @classmethod
    def poll(cls, context):
        return in_blobtree_editor(context)

    def draw(self, context):
        for menu in SUBMENU_CLASSES:
            self.layout.menu(menu.bl_idname)


def draw_in_node_add_menu(self, context):
    """Appended to Blender's NODE_MT_add: in a BlobTree editor it lists our menus."""
    if in_blobtree_editor(context):
        self.layout.menu_contents(NODE_MT_blobtree_ink_add.bl_idname)


classes = (*SUBMENU_CLASSES, NODE_MT_blobtree_ink_add)


def register():
    for c in classes:
        bpy.utils.register_class(c)
    bpy.types.NODE_MT_add.append(draw_in_node_add_menu)


def unregister():
    bpy.types.NODE_MT_add.remove(draw_in_node_add_menu)
    for c in reversed(classes):
        bpy.utils.unregister_class(c)
