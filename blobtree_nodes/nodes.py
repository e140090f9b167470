"""The BlobTree nodes: one class per format type, plus the Model Output node.

Primitives are leaves; blend, ricci, union, intersection and difference take any
number of inputs (a new empty socket appears when the last one is linked); transform
and the warps take one. Vectors can come from a linked object instead: a primitive's
centre (or a segment's ends) from objects' world locations, a transform's translate,
rotate and scale from an object (an Empty the artist moves in the viewport).
"""
import bpy

from ..model import nodes as N
from . import props
from .base import BlobTreeNode, ensure_trailing_input, input_name, new_input, on_edit
from .sockets import SOCKET

LABEL = {"point": "Point", "segment": "Segment", "circle": "Circle", "disc": "Disc", "box": "Box",
         "blend": "Blend", "ricci": "Ricci Blend", "union": "Union", "intersection": "Intersection",
         "difference": "Difference", "transform": "Transform", "twist": "Twist", "taper": "Taper",
         "bend": "Bend"}
# each node type's tooltip (in the Add menu and on the node)
DOC = {
    "point": "A ball: the field falls off with the distance from a point",
    "segment": "A capsule: the field falls off with the distance from a line segment",
    "circle": "A ring (a torus): the field falls off with the distance from a circle",
    "disc": "A rounded coin: the field falls off with the distance from a flat disc",
    "box": "A rounded box: the field falls off with the distance from a solid box",
    "blend": "Melts its inputs together smoothly: the sum of their fields",
    "ricci": "Blends its inputs with an exponent that sets how sharply they meet "
             "(1: a blend; large: a union)",
    "union": "Joins its inputs with a sharp crease: the largest of their fields",
    "intersection": "Keeps only where all its inputs overlap: the smallest of their fields",
    "difference": "Carves every Subtract input out of the Base input",
    "transform": "Moves, rotates and scales its input, by the values here or by following an object",
    "twist": "Twists its input about its Z axis, more with height",
    "taper": "Widens (or narrows) its input in X and Y along its Z axis",
    "bend": "Bends its input: its X axis curls into an arc (towards +Z for a positive curvature)",
}
ICON = {"point": "MESH_UVSPHERE", "segment": "MESH_CAPSULE", "circle": "MESH_TORUS", "disc": "MESH_CIRCLE",
        "box": "MESH_CUBE", "blend": "SELECT_EXTEND", "ricci": "SELECT_EXTEND", "union": "SELECT_EXTEND",
        "intersection": "SELECT_INTERSECT", "difference": "SELECT_SUBTRACT", "transform": "OBJECT_ORIGIN",
        "twist": "MOD_SIMPLEDEFORM", "taper": "MOD_SIMPLEDEFORM", "bend": "MOD_SIMPLEDEFORM"}
# which vector keys may come from an object's world location
OBJECT_KEYS = {"point": ("center",), "segment": ("a", "b"), "circle": ("center",), "disc": ("center",),
               "box": ("center",)}
# node widths: room for a vector component with two decimals, and for the labels
PRIMITIVE_WIDTH = 190
OPERATOR_WIDTH = 160
WARP_WIDTH = 180
OUTPUT_WIDTH = 190


def idname(kind):
    return "BlobTreeInk" + "".join(p.capitalize() for p in kind.split("_")) + "Node"


def follow_label(kind, key):
    """The name of the object picker that drives a vector key."""
    return f"{props.label(kind, key)} Follows"


FOLLOW_HINT = "Follow Object"      # what an empty object picker says


def draw_value(layout, node, key):
    """A property of the format's keys; a vector as a column under its name, one
    component a row, so that each shows its two decimals. A vector an object can drive
    has the object picker first in that column, and shows no numbers while it follows."""
    if not props.is_vector(node.kind, key):
        layout.prop(node, key)
        return
    col = layout.column(align=True)
    col.label(text=f"{props.label(node.kind, key)}:")
    obj_key = f"{key}_object"
    if hasattr(node, obj_key):
        col.prop(node, obj_key, text="", placeholder=FOLLOW_HINT)
        if getattr(node, obj_key) is not None:
            return
    col.prop(node, key, text="")


class _Primitive(BlobTreeNode):
    bl_width_default = PRIMITIVE_WIDTH

    def init(self, context):
        self.outputs.new(SOCKET, "Field")

    def draw_props(self, context, layout):
        for key in props.value_keys(self.kind):
            draw_value(layout, self, key)


_initialising = [0]   # socket changes inside init() or a build call update(); ignore those


class suspend_socket_updates:
    """Context manager: n-ary nodes leave their sockets alone while a tree is built."""

    def __enter__(self):
        _initialising[0] += 1

    def __exit__(self, *exc):
        _initialising[0] -= 1


class _Nary(BlobTreeNode):
    bl_width_default = OPERATOR_WIDTH
    first_label = None      # difference: the first input is the base
    input_label = "Field"   # the others are numbered: "Field 1", "Field 2", ...

    @classmethod
    def fixed_inputs(cls):
        return 1 if cls.first_label else 0

    def init(self, context):
        _initialising[0] += 1
        try:
            self.outputs.new(SOCKET, "Field")
            if self.first_label:
                new_input(self, self.first_label)
            new_input(self, input_name(self.input_label, 1))
        finally:
            _initialising[0] -= 1

    def update(self):
        if _initialising[0] or not self.inputs:
            return
        ensure_trailing_input(self, self.fixed_inputs(), self.input_label)

    def draw_props(self, context, layout):
        for key in props.value_keys(self.kind):
            draw_value(layout, self, key)


class _Unary(BlobTreeNode):
    bl_width_default = WARP_WIDTH

    def init(self, context):
        self.outputs.new(SOCKET, "Field")
        new_input(self, "Field")

    def draw_props(self, context, layout):
        if self.kind == "transform":
            col = layout.column(align=True)
            col.label(text=f"{self.bl_rna.properties['source_object'].name}:")
            col.prop(self, "source_object", text="")
            if self.source_object is not None:
                return
        for key in props.value_keys(self.kind):
            draw_value(layout, self, key)


def _make(kind, base):
    ann = props.annotations(kind)
    for key in OBJECT_KEYS.get(kind, ()):
        ann[f"{key}_object"] = bpy.props.PointerProperty(
            type=bpy.types.Object, name=follow_label(kind, key), update=on_edit,
            description=f"Keep the {props.label(kind, key).lower()} at this object's world location "
                        "(e.g. an Empty moved in the viewport); empty: use the values below")
    if kind == "transform":
        ann["source_object"] = bpy.props.PointerProperty(
            type=bpy.types.Object, name="Follow Object", update=on_edit,
            description="Take translate, rotate and scale from this object's world transform "
                        "(e.g. an Empty); empty: use the values below")
    attrs = {"bl_idname": idname(kind), "bl_label": LABEL[kind], "bl_icon": ICON[kind], "kind": kind,
             "__annotations__": ann, "__doc__": DOC[kind]}
    if kind == "difference":
        attrs["first_label"] = "Base"
        attrs["input_label"] = "Subtract"
    return type(idname(kind) + "Class", (base, bpy.types.Node), attrs)


PRIMITIVE_CLASSES = tuple(_make(k, _Primitive) for k in N.PRIMITIVES)
OPERATOR_CLASSES = tuple(_make(k, _Nary) for k in N.OPERATORS)
WARP_CLASSES = tuple(_make(k, _Unary) for k in N.UNARY)


class BlobTreeOutputNode(BlobTreeNode, bpy.types.Node):
    """The model: the field that reaches this node is what gets illustrated"""
    bl_idname = "BlobTreeInkOutputNode"
    bl_label = "Model Output"
    bl_icon = "OUTPUT"
    bl_width_default = OUTPUT_WIDTH
    kind = "output"

    def init(self, context):
        new_input(self, "Model")

    def draw_props(self, context, layout):
        tree = self.id_data
        layout.prop(tree, "iso")
        layout.prop(tree, "preview_resolution")


classes = (*PRIMITIVE_CLASSES, *OPERATOR_CLASSES, *WARP_CLASSES, BlobTreeOutputNode)
BY_KIND = {c.kind: c for c in classes}
