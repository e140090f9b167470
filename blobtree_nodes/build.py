"""Build a BlobTree node tree from a model (the JSON importer's Blender half).

Layout: the Model Output on the right, then one column per depth going left; inside a
column nodes keep the order of a depth-first walk, so siblings stay together.
"""
import gc
import json

from ..model import nodes as N
from . import preview, props
from .base import new_input
from .nodes import idname, suspend_socket_updates

COLUMN = 260.0
ROW = 60.0


def build_tree(tree, model):
    """Fill an empty BlobTree node tree with the model's nodes and links."""
    # thousands of short-lived RNA wrappers trigger Python's cyclic collector over
    # Blender's whole object graph again and again: pause it while building
    was_enabled = gc.isenabled()
    gc.disable()
    with preview.hold():                  # one preview schedule for the whole import
        try:
            with suspend_socket_updates():
                made = _build(tree, model)
        finally:
            if was_enabled:
                gc.enable()
        for bn in made:                   # now give every operator its empty trailing socket
            if bn.kind in N.OPERATORS:
                bn.update()
    return tree


def _build(tree, model):
    tree.nodes.clear()
    out = tree.nodes.new("BlobTreeInkOutputNode")
    out.location = (COLUMN, 0.0)
    _set_iso(tree, model.iso)
    tree.model_name = model.name
    rows = {}                                  # depth -> next y
    counts = {}
    where = []
    pending_links = []
    stack = [(model.root, 0, out.inputs[0])]
    made = []
    while stack:
        node, depth, target = stack.pop()
        kind = N.TYPE_NAME[type(node)]
        bn = tree.nodes.new(idname(kind))
        # name it at once so that the default name stays free: Blender's search for a
        # free "Point.NNN" is linear per node, quadratic for a thousand points
        counts[kind] = counts.get(kind, 0) + 1
        bn.name = f"{bn.bl_label}.{counts[kind]:03d}"
        made.append(bn)
        y = rows.get(depth, 0.0)
        where.append((-COLUMN * depth, y))
        rows[depth] = y - _height(kind, len(getattr(node, "children", ())))
        if node.name is not None:
            bn.label = node.name
        bn.set_exact_many({key: (list(v) if isinstance(v, tuple) else v)
                           for key in props.value_keys(kind) for v in (getattr(node, key),)})
        pending_links.append((bn, target))
        if kind in N.OPERATORS:
            kids = node.children
            # sockets: the node starts with its own (Base + one, or one); add the rest
            first = 1 if kind == "difference" else 0
            while len(bn.inputs) < len(kids):
                new_input(bn, "Subtract" if first else "Field", fresh=True)
            for child, sock in reversed(list(zip(kids, bn.inputs))):
                stack.append((child, depth + 1, sock))
        elif kind in N.UNARY:
            stack.append((node.child, depth + 1, bn.inputs[0]))
    # links after all nodes: adding nodes to a tree full of links is slower
    for bn, target in pending_links:
        tree.links.new(bn.outputs[0], target, verify_limits=False)
    # one bulk write: setting node.location one by one costs O(nodes) each
    locs = [0.0] * (2 * len(tree.nodes))
    tree.nodes.foreach_get("location", locs)
    index = {n.as_pointer(): i for i, n in enumerate(tree.nodes)}
    for bn, (x, y) in zip(made, where):
        i = index[bn.as_pointer()]
        locs[2 * i], locs[2 * i + 1] = x, y
    tree.nodes.foreach_set("location", locs)
    for n in tree.nodes:
        n.select = False
    return made


def _set_iso(tree, iso):
    tree.iso = iso
    tree.exact_iso = json.dumps([float(iso), float(tree.iso)])


def _height(kind, n_children):
    """About how tall Blender draws a node of this kind (header, sockets, properties)."""
    rows = sum(4 if props.is_vector(kind, k) else 1 for k in props.value_keys(kind)) + n_children
    rows += {"point": 1, "segment": 2, "circle": 1, "disc": 1, "box": 1, "transform": 1}.get(kind, 0)
    return 50.0 + 22.0 * (rows + 2) + ROW / 3
