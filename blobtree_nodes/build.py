"""Build a BlobTree node tree from a model (the JSON importer's Blender half).

Layout: the Model Output on the right, then one column per depth going left; inside a
column nodes keep the order of a depth-first walk, so siblings stay together.
"""
import gc
import json

from ..model import nodes as N
from . import changes, props
from .base import input_name, new_input
from .nodes import LABEL, idname, suspend_socket_updates

COLUMN = 260.0
ROW = 60.0


def build_tree(tree, model):
    """Fill an empty BlobTree node tree with the model's nodes and links."""
    # thousands of short-lived RNA wrappers trigger Python's cyclic collector over
    # Blender's whole object graph again and again: pause it while building
    was_enabled = gc.isenabled()
    gc.disable()
    with changes.hold():                  # one preview schedule for the whole import
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


class _NamesFromLabels:
    """Give each new node its final name through its type's label.

    Blender names a new node after its type's label and, if that name is taken, tries
    "Label.001", "Label.002", ... each against every node: quadratic for a thousand
    points. Renaming a node afterwards is no cure: a rename runs a full tree update,
    as costly as adding the node. Setting ``bl_label`` on a node sets its type's
    label, so before each new node the label is set to the name it should get;
    afterwards every label is restored (also on an error).
    """

    def __enter__(self):
        self.counts = {}
        self.instances = {}                # kind -> a node of that type (to set its label)
        return self

    def new(self, tree, kind):
        k = self.counts.get(kind, 0)
        self.counts[kind] = k + 1
        inst = self.instances.get(kind)
        if inst is not None:
            inst.bl_label = f"{LABEL[kind]}.{k:03d}"
        node = tree.nodes.new(idname(kind))
        self.instances.setdefault(kind, node)
        return node

    def __exit__(self, *exc):
        for kind, inst in self.instances.items():
            inst.bl_label = LABEL[kind]


def _build(tree, model):
    tree.nodes.clear()
    out = tree.nodes.new("BlobTreeInkOutputNode")
    out.location = (COLUMN, 0.0)
    _set_iso(tree, model.iso)
    tree.model_name = model.name
    rows = {}                                  # depth -> next y
    where = []
    pending_links = []
    stack = [(model.root, 0, out.inputs[0])]
    made = []
    with _NamesFromLabels() as names:     # restored before the links, whose updates see it
        while stack:
            node, depth, target = stack.pop()
            bn = _add_node(tree, names, node, depth, rows, where, stack)
            made.append(bn)
            pending_links.append((bn, target))
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


def _add_node(tree, names, node, depth, rows, where, stack):
    """Make one node (its properties, position and input sockets); push its children."""
    kind = N.TYPE_NAME[type(node)]
    bn = names.new(tree, kind)
    y = rows.get(depth, 0.0)
    where.append((-COLUMN * depth, y))
    rows[depth] = y - _height(kind, len(getattr(node, "children", ())))
    if node.name is not None:
        bn.label = node.name
    bn.set_exact_many({key: (list(v) if isinstance(v, tuple) else v)
                       for key in props.value_keys(kind) for v in (getattr(node, key),)})
    if kind in N.OPERATORS:
        kids = node.children
        # sockets: the node starts with its own (Base + one, or one); add the rest
        first = bn.fixed_inputs()
        while len(bn.inputs) < len(kids):
            new_input(bn, input_name(bn.input_label, len(bn.inputs) - first + 1), fresh=True)
        for child, sock in reversed(list(zip(kids, bn.inputs))):
            stack.append((child, depth + 1, sock))
    elif kind in N.UNARY:
        stack.append((node.child, depth + 1, bn.inputs[0]))
    return bn


def _set_iso(tree, iso):
    tree.iso = iso
    tree.exact_iso = json.dumps([float(iso), float(tree.iso)])


def _height(kind, n_children):
    """About how tall Blender draws a node of this kind (header, sockets, properties)."""
    rows = sum(4 if props.is_vector(kind, k) else 1 for k in props.value_keys(kind)) + n_children
    rows += {"point": 1, "segment": 2, "circle": 1, "disc": 1, "box": 1, "transform": 1}.get(kind, 0)
    return 50.0 + 22.0 * (rows + 2) + ROW / 3
