"""Build a BlobTree node tree from a model (the JSON importer's Blender half).

Layout: the Model Output on the right, then one column per depth going left; inside a
column nodes keep the order of a depth-first walk, so siblings stay together. A column
taller than the layout's height (that of a 16:9 box holding every node, at least
SHORTEST_WRAP) wraps into several side by side, so a wide tree (the heart's 66 segments
at one depth) is a block the editor's View All shows readably, not one tall column.
"""
import gc
import json

from ..model import nodes as N
from . import changes, props
from .base import input_name, new_input
from .nodes import LABEL, idname, suspend_socket_updates
from .tree import blobtrees

COLUMN = 260.0
ROW = 60.0
ASPECT = 16.0 / 9.0          # the imported layout's width over its height, about
SHORTEST_WRAP = 1500.0       # a column shorter than this never wraps (about a screen of nodes)


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


def _own_name(tree, name):
    """The model's name for the tree (its ink is named after it): ``name``, or the
    tree's own (unique) name where another tree's model has that name already (the
    same model imported twice must not draw into one ink)."""
    taken = {t.model_name or t.name for t in blobtrees() if t != tree}
    own, k = name, 0
    while own in taken:
        k += 1
        own = tree.name if k == 1 else f"{tree.name}.{k:03d}"
    return own


def _build(tree, model):
    tree.nodes.clear()
    out = tree.nodes.new("BlobTreeInkOutputNode")
    out.location = (COLUMN, 0.0)
    _set_iso(tree, model.iso)
    tree.model_name = _own_name(tree, model.name)
    where = []                                 # (depth, height) of each node made, in order
    pending_links = []
    stack = [(model.root, 0, out.inputs[0])]
    made = []
    with _NamesFromLabels() as names:     # restored before the links, whose updates see it
        while stack:
            node, depth, target = stack.pop()
            bn = _add_node(tree, names, node, depth, where, stack)
            made.append(bn)
            pending_links.append((bn, target))
    # links after all nodes: adding nodes to a tree full of links is slower
    for bn, target in pending_links:
        tree.links.new(bn.outputs[0], target, verify_limits=False)
    # one bulk write: setting node.location one by one costs O(nodes) each
    locs = [0.0] * (2 * len(tree.nodes))
    tree.nodes.foreach_get("location", locs)
    index = {n.as_pointer(): i for i, n in enumerate(tree.nodes)}
    for bn, (x, y) in zip(made, _layout(where)):
        i = index[bn.as_pointer()]
        locs[2 * i], locs[2 * i + 1] = x, y
    tree.nodes.foreach_set("location", locs)
    for n in tree.nodes:
        n.select = False
    return made


def _layout(where):
    """(x, y) of each node from its (depth, height), in the order made: a column per
    depth going left from the Model Output, wrapped into side-by-side columns where it
    is taller than the layout's height."""
    tall = max(SHORTEST_WRAP, (sum(h for _, h in where) * COLUMN / ASPECT) ** 0.5)
    depths = sorted({d for d, _ in where})
    columns, placed = {}, []                   # depth -> its columns' next y; (depth, column, y)
    for d, h in where:
        col = columns.setdefault(d, [0.0])
        if col[-1] < 0 and col[-1] - h < -tall:
            col.append(0.0)                    # this column is full: a new one beside it
        placed.append((d, len(col) - 1, col[-1]))
        col[-1] -= h
    left, x0 = 0, {}
    for d in depths:                           # each depth's first column left of the last depth's
        x0[d] = left
        left += len(columns[d])
    return [(-COLUMN * (x0[d] + c), y) for d, c, y in placed]


def _add_node(tree, names, node, depth, where, stack):
    """Make one node (its properties and input sockets), note its depth and height;
    push its children."""
    kind = N.TYPE_NAME[type(node)]
    bn = names.new(tree, kind)
    where.append((depth, _height(kind, len(getattr(node, "children", ())))))
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
