"""Add-menu categories of the BlobTree node editor: Primitives, Operators, Warps, Output."""
import nodeitems_utils
from nodeitems_utils import NodeCategory, NodeItem

from ..model import nodes as N
from .nodes import BlobTreeOutputNode, idname


class BlobTreeCategory(NodeCategory):
    @classmethod
    def poll(cls, context):
        return context.space_data.tree_type == "BlobTreeInkNodeTree"


CATEGORIES = [
    BlobTreeCategory("BLOBTREE_INK_PRIMITIVES", "Primitives", items=[NodeItem(idname(k)) for k in N.PRIMITIVES]),
    BlobTreeCategory("BLOBTREE_INK_OPERATORS", "Operators", items=[NodeItem(idname(k)) for k in N.OPERATORS]),
    BlobTreeCategory("BLOBTREE_INK_WARPS", "Warps", items=[NodeItem(idname(k)) for k in N.UNARY]),
    BlobTreeCategory("BLOBTREE_INK_OUTPUT", "Output", items=[NodeItem(BlobTreeOutputNode.bl_idname)]),
]
KEY = "BLOBTREE_INK_NODES"


def register():
    nodeitems_utils.register_node_categories(KEY, CATEGORIES)


def unregister():
    nodeitems_utils.unregister_node_categories(KEY)
