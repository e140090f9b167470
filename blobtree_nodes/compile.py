"""Compile a BlobTree node tree to the pure model (blobtree-1 document, then Model).

The tree is turned into a plain blobtree-1 document while recording which node each
JSON path came from; the format's own validation then checks every value, and an
error is put back on the node its path names. Structural problems (no output, an
operator with nothing linked, a link from a foreign socket, a cycle) are found while
walking the tree. Nothing downstream runs on a broken tree.
"""
import json

import bpy

from ..model import format as F
from . import props
from .base import TREE, shown_name
from .nodes import BY_KIND

class TreeError(Exception):
    """A node tree that cannot compile; ``node`` is the offending node (or None)."""

    def __init__(self, node, message):
        super().__init__(message)
        self.node = node
        self.message = message

    def __str__(self):
        where = f"node '{shown_name(self.node)}': " if self.node is not None else ""
        return where + self.message


def output_nodes(tree):
    """The tree's Model Output nodes that count (not muted)."""
    return [n for n in tree.nodes if n.bl_idname == "BlobTreeInkOutputNode" and not n.mute]


def output_node(tree):
    outs = output_nodes(tree)
    if not outs:
        raise TreeError(None, f"tree '{tree.name}' has no Model Output node")
    active = [n for n in outs if n.is_active_output] if hasattr(outs[0], "is_active_output") else []
    return active[0] if len(active) == 1 else outs[0]


def _linked_from(socket, incoming):
    """The node feeding an input socket, through reroutes; None if unlinked.
    ``incoming`` maps input-socket pointers to links (NodeSocket.links scans every link
    of the tree, which made compiling a 1500-node tree quadratic)."""
    seen = 0
    while socket.is_linked:
        link = incoming.get(socket.as_pointer())
        if link is None:
            return None
        if not link.is_valid:
            raise TreeError(link.to_node, f"the link from '{link.from_node.name}' is invalid "
                            "(a cycle or an incompatible socket)")
        node = link.from_node
        if node.bl_idname == "NodeReroute":
            socket = node.inputs[0]
            seen += 1
            if seen > 10000:
                raise TreeError(node, "reroute loop")
            continue
        if getattr(node, "kind", None) not in BY_KIND or node.kind == "output":
            raise TreeError(link.to_node, f"'{node.name}' is not a BlobTree field node")
        return node
    return None


class Followed:
    """The objects a tree's nodes follow, as the tree sees them: evaluated (animation,
    parents, constraints: the depsgraph's) and in the model's coordinates (the inverse of
    the placement of the model, its preview object's matrix)."""

    def __init__(self, tree, depsgraph=None):
        self.depsgraph = depsgraph
        placement = tree.preview_object
        self.inverse = self.world(placement).inverted_safe() if placement is not None else None

    def world(self, obj):
        if self.depsgraph is None:
            self.depsgraph = bpy.context.evaluated_depsgraph_get()
        return obj.evaluated_get(self.depsgraph).matrix_world

    def matrix(self, obj):
        m = self.world(obj)
        return m if self.inverse is None else self.inverse @ m


def in_no_scene(obj):
    """Whether a followed object is gone from every scene: deleted in the viewport (a
    node's pointer keeps it in bpy.data, where nothing evaluates its animation any more)
    or appended without being linked into one."""
    return obj is not None and not obj.users_scene


def _in_a_scene(node, obj):
    """The object a node follows (or None), unless it is in no scene (:func:`in_no_scene`)."""
    if in_no_scene(obj):
        raise TreeError(node, f"the object '{obj.name}' it follows was deleted (it is in no scene): "
                              "link it into a scene, pick another or clear the field")
    return obj


def _node_doc(node, followed):
    """This node's own keys (no children) as a blobtree-1 fragment."""
    d = {"type": node.kind}
    if node.label:
        d["name"] = node.label
    if node.kind == "transform" and _in_a_scene(node, node.source_object) is not None:
        loc, rot, scale = followed.matrix(node.source_object).decompose()
        eul = rot.to_euler("XYZ")
        d.update(translate=[float(x) for x in loc], rotate=[float(x) for x in eul],
                 scale=[float(x) for x in scale])
        return d
    for key in props.value_keys(node.kind):
        obj = _in_a_scene(node, getattr(node, f"{key}_object", None))
        d[key] = [float(x) for x in followed.matrix(obj).translation] if obj is not None else node.value(key)
    return d


def tree_document(tree, depsgraph=None):
    """(document, paths): the blobtree-1 document and {json path: node}; followed objects
    as ``depsgraph`` evaluates them (default: the context's)."""
    followed = Followed(tree, depsgraph)
    out = output_node(tree)
    incoming = {link.to_socket.as_pointer(): link for link in tree.links}
    root_node = _linked_from(out.inputs[0], incoming)
    if root_node is None:
        raise TreeError(out, "nothing is linked to the Model Output")
    paths = {}
    on_path = set()

    def walk(node, path, depth):
        if depth > F.MAX_DEPTH:
            raise TreeError(node, f"the tree is nested deeper than {F.MAX_DEPTH} levels")
        key = node.as_pointer()
        if key in on_path:
            raise TreeError(node, "the tree has a cycle through this node")
        on_path.add(key)
        paths[path] = node
        d = _node_doc(node, followed)
        if node.mute:
            raise TreeError(node, "muted nodes are not supported; unmute it or unlink it")
        if node.kind in ("blend", "ricci", "union", "intersection", "difference"):
            kids = [c for c in (_linked_from(s, incoming) for s in node.inputs) if c is not None]
            least = 2 if node.kind == "difference" else 1
            if node.kind == "difference" and not node.inputs[0].is_linked:
                raise TreeError(node, "the Base input is not linked")
            if len(kids) < least:
                raise TreeError(node, f"needs at least {least} linked input{'s' if least > 1 else ''}")
            d["children"] = [walk(c, f"{path}.children[{i}]", depth + 1) for i, c in enumerate(kids)]
        elif node.kind in ("transform", "twist", "taper", "bend"):
            c = _linked_from(node.inputs[0], incoming)
            if c is None:
                raise TreeError(node, "its input is not linked")
            d["child"] = walk(c, f"{path}.child", depth + 1)
        on_path.discard(key)
        return d

    doc = {"format": F.FORMAT, "name": tree.model_name or tree.name, "root": walk(root_node, "root", 0)}
    iso = _tree_iso(tree)
    if iso != 0.5:
        doc["iso"] = iso
    return doc, paths


def _tree_iso(tree):
    cur = float(tree.iso)
    if tree.exact_iso:
        exact, snap = json.loads(tree.exact_iso)
        if snap == cur:
            return exact
    return cur


def _node_for_error(message, paths):
    """The node whose JSON path is the longest prefix of the message's path."""
    head = message.split(":", 1)[0]
    best = None
    for p, node in paths.items():
        if head == p or head.startswith(p + ".") or head.startswith(p + "["):
            if best is None or len(p) > len(best[0]):
                best = (p, node)
    return best


def compile_tree(tree, mark=True, depsgraph=None):
    """The tree's Model as it is now (its animated values, its followed objects as
    ``depsgraph`` evaluates them: default the context's); raises TreeError naming the
    node (and marks it) when broken."""
    return compile_document(tree, mark, depsgraph)[0]


def compile_document(tree, mark=True, depsgraph=None):
    """:func:`compile_tree`'s Model and the blobtree-1 document it was made from."""
    if tree.bl_idname != TREE:
        raise TreeError(None, f"'{tree.name}' is not a BlobTree node tree")
    try:
        try:
            doc, paths = tree_document(tree, depsgraph)
        except RecursionError:
            raise TreeError(None, "the tree is nested too deeply") from None
        try:
            model = F.from_dict(doc)
        except F.ModelError as e:
            msg = str(e)
            found = _node_for_error(msg, paths)
            if found is None:
                if msg.startswith("document.iso"):         # the Model Output node shows the tree's Iso Value
                    raise TreeError(output_node(tree), "Iso Value " + msg.split(":", 1)[1].strip()) from None
                raise TreeError(None, msg) from None
            path, node = found
            detail = msg[len(path):].lstrip(".")
            raise TreeError(node, _friendly(node.kind, detail)) from None
    except TreeError as e:
        if mark:
            show_outcome(tree, e)
        raise
    if mark:
        show_outcome(tree)
    return model, doc


def show_outcome(tree, error=None):
    """Show a compile's outcome on the tree's nodes: the errors shown before cleared,
    and ``error``'s node (a TreeError's) marked with its message."""
    clear_errors(tree)
    if error is not None and error.node is not None:
        error.node.set_error(error.message)


def same_model(tree, document):
    """Whether the tree still makes ``document`` (its blobtree-1 document taken before):
    edits counted since then changed nothing of the model (its Live Preview switched,
    its collection set when its first ink was drawn)."""
    try:
        return tree_document(tree)[0] == document
    except (TreeError, RecursionError):
        return False


def _friendly(kind, detail):
    # "radius: must be > 0, got 0" -> "Influence Radius must be > 0, got 0"
    key, _, rest = detail.partition(":")
    base = key.split("[")[0]
    label = props.label(kind, base)
    return f"{label}{key[len(base):]} {rest.strip()}" if rest else detail


def clear_errors(tree):
    for n in tree.nodes:
        if getattr(n, "error", ""):
            n.set_error("")


def tree_model_or_none(tree):
    """The model, or None (with the error marked on the node) for a broken tree."""
    try:
        return compile_tree(tree)
    except TreeError:
        return None


def is_blobtree(tree):
    return isinstance(tree, bpy.types.NodeTree) and tree.bl_idname == TREE

