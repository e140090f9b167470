"""What every BlobTree node shares: the tree poll, the error shown on the node (wrapped
to the node's width, its whole text also in the icon's tooltip), exact values kept for
round trips, live-preview scheduling on edits, and the numbered inputs of n-ary nodes.

Blender stores float properties in single precision. So that a model imported from
JSON exports (and evaluates) with its exact double values, the importer records each
value next to the single-precision number it put in the property; as long as the
property still holds that number the exact value is used, and an edit by the artist
simply wins.
"""
import json

import bpy

from . import changes, wrap
from .idnames import TREE
from .sockets import SOCKET

ERROR_COLOR = (0.65, 0.12, 0.12)
SHOW_ERROR = "blobtree_ink.show_node_error"     # its tooltip is the node's whole error


def shown_name(node):
    """A node as the artist sees it in the editor and every message names it: its label,
    else its name."""
    return node.label or node.name


def in_blobtree_editor(context):
    """The context is a node editor showing BlobTree trees."""
    return getattr(context.space_data, "tree_type", "") == TREE


def on_edit(self, context):
    """Property update callback: the tree changed, schedule its preview."""
    tree = self.id_data
    if isinstance(tree, bpy.types.NodeTree) and tree.bl_idname == TREE:
        changes.schedule(tree)


class BlobTreeNode:
    """Mixin for all BlobTree nodes. Subclasses set ``kind`` (the format type)."""
    kind = ""
    error: bpy.props.StringProperty(name="Error", options={"SKIP_SAVE"},
                                    description="Why the tree cannot be compiled at this node (empty when it can)")
    exact: bpy.props.StringProperty(name="Exact Values", options={"HIDDEN"},
                                    description="The exact imported values behind the single-precision properties")

    @classmethod
    def poll(cls, ntree):
        return ntree.bl_idname == TREE

    def draw_buttons(self, context, layout):
        # the error below the values: one that comes or goes moves no field under the pointer
        self.draw_props(context, layout)
        if self.error:
            draw_error(layout, context, self, wrap.node_text_width(context, self.width))

    def draw_buttons_ext(self, context, layout):
        # the sidebar: its Errors panel shows the error at the sidebar's width
        self.draw_props(context, layout)

    def draw_props(self, context, layout):
        pass

    # --- exact values ---------------------------------------------------------------
    def set_exact(self, key, value):
        """Set a property from a double (or a 3-vector of doubles) and remember it."""
        self.set_exact_many({key: value})

    def set_exact_many(self, values):
        """set_exact for several properties, with one write of the record."""
        d = json.loads(self.exact) if self.exact else {}
        for key, value in values.items():
            setattr(self, key, value)
            stored = getattr(self, key)
            snap = list(stored) if hasattr(stored, "__len__") else float(stored)
            d[key] = [list(value) if hasattr(value, "__len__") else float(value), snap]
        self.exact = json.dumps(d)

    def value(self, key):
        """The property's value as doubles: the exact imported value while unedited."""
        cur = getattr(self, key)
        cur = [float(x) for x in cur] if hasattr(cur, "__len__") else float(cur)
        if self.exact:
            d = json.loads(self.exact)
            if key in d and d[key][1] == cur:
                return d[key][0]
        return cur

    def set_error(self, message):
        # write only on change: writes notify the tree, which would schedule another
        # preview rebuild, which would write again
        if self.error != message:
            self.error = message
        if self.use_custom_color != bool(message):
            self.use_custom_color = bool(message)
        if message and tuple(self.color) != ERROR_COLOR:
            self.color = ERROR_COLOR


def draw_error(layout, context, node, width):
    """The node's whole error in a red box, wrapped to ``width`` text pixels; hovering
    the icon shows the whole message as a tooltip."""
    box = layout.box()
    box.alert = True
    col = box.column(align=True)
    for i, line in enumerate(wrap.lines(node.error, width, context)):
        row = col.row(align=True)
        if i == 0:
            op = row.operator(SHOW_ERROR, text="", icon="ERROR", emboss=False)
            op.tree_name = node.id_data.name
            op.node_name = node.name
        else:
            row.label(text="", icon="BLANK1")
        row.label(text=line)


def input_name(name, number):
    """An n-ary node's numbered inputs: "Field 1", "Field 2", ... ("Subtract 1", ...)."""
    return f"{name} {number}"


def new_input(node, name, fresh=False):
    # an explicit identifier spares Blender its linear search for a free one, which
    # makes adding sockets to a node with hundreds of inputs quadratic; ``fresh``: the
    # node's inputs were all made here, in0..in{k-1}, so in{k} is free
    ins = node.inputs
    ident = f"in{len(ins)}"
    if not fresh and ident in {s.identifier for s in ins}:
        ident = f"in{max(int(s.identifier[2:]) for s in ins if s.identifier[2:].isdigit()) + 1}" \
            if any(s.identifier[2:].isdigit() for s in ins) else f"in{len(ins)}x"
    return ins.new(SOCKET, name, identifier=ident)


def ensure_trailing_input(node, keep_first, name):
    """N-ary inputs the Blender way: one empty socket after the linked ones, numbered
    from 1 after the ``keep_first`` fixed ones (a name is written only when it changes)."""
    ins = node.inputs
    for s in list(ins)[keep_first:-1]:
        if not s.is_linked:
            ins.remove(s)
    if len(ins) <= keep_first or ins[-1].is_linked:
        new_input(node, input_name(name, len(ins) - keep_first + 1))
    for number, s in enumerate(list(ins)[keep_first:], 1):
        want = input_name(name, number)
        if s.name != want:
            s.name = want
