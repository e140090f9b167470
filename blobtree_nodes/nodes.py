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

LABEL = {"point": "Point", "segment": "Segment", "circle": "Circle", "disc": "Disc", "box": "Box",
         "blend": "Blend", "ricci": "Ricci Blend", "union": "Union", "intersection": "Intersection",
         "difference": "Difference", "transform": "Transform", "twist": "Twist", "taper": "Taper",
         "bend": "Bend"}
ICON = {"point": "MESH_UVSPHERE", "segment": "MESH_CAPSULE", "circle": "MESH_TORUS", "disc": "MESH_CIRCLE",
        "box": "MESH_CUBE", "blend": "SELECT_EXTEND", "ricci": "SELECT_EXTEND", "union": "SELECT_EXTEND",
        "intersection": "SELECT_INTERSECT", "difference": "SELECT_SUBTRACT", "transform": "OBJECT_ORIGIN",
        "twist": "MOD_SIMPLEDEFORM", "taper": "MOD_SIMPLEDEFORM", "bend": "MOD_SIMPLEDEFORM"}
# which vector keys may come from an object's world location
OBJECT_KEYS = {"point": ("center",), "segment": ("a", "b"), "circle": ("center",), "disc": ("center",),
               "box": ("center",)}


def idname(kind):
    return "BlobTreeInk" + "".join(p.capitalize() for p in kind.split("_")) + "Node"


class _Primitive(BlobTreeNode):
    bl_width_default = 190
    def init(self, context):
        self.outputs.new("BlobTreeInkFieldSocket", "Field")

    def draw_props(self, context, layout):
        for key in props.value_keys(self.kind):
            obj_key = f"{key}_object"
            if hasattr(self, obj_key):
                row = layout.row(align=True)
                row.prop(self, obj_key, text=props.LABELS[key])
                if getattr(self, obj_key) is not None:
                    continue
            layout.prop(self, key)


_initialising = [0]   # socket changes inside init() or a build call update(); ignore those


class suspend_socket_updates:
    """Context manager: n-ary nodes leave their sockets alone while a tree is built."""

    def __enter__(self):
        _initialising[0] += 1

    def __exit__(self, *exc):
        _initialising[0] -= 1


class _Nary(BlobTreeNode):
    first_label = None      # difference: the first input is the base
    input_label = "Field"   # the others are numbered: "Field 1", "Field 2", ...

    @classmethod
    def fixed_inputs(cls):
        return 1 if cls.first_label else 0

    def init(self, context):
        _initialising[0] += 1
        try:
            self.outputs.new("BlobTreeInkFieldSocket", "Field")
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
            layout.prop(self, key)


class _Unary(BlobTreeNode):
    bl_width_default = 180
    def init(self, context):
        self.outputs.new("BlobTreeInkFieldSocket", "Field")
        new_input(self, "Field")

    def draw_props(self, context, layout):
        if self.kind == "transform":
            layout.prop(self, "source_object", text="Object")
            if self.source_object is not None:
                return
        for key in props.value_keys(self.kind):
            layout.prop(self, key)


def _make(kind, base):
    ann = props.annotations(kind)
    for key in OBJECT_KEYS.get(kind, ()):
        ann[f"{key}_object"] = bpy.props.PointerProperty(
            type=bpy.types.Object, name=f"{props.LABELS[key]} Object", update=on_edit,
            description=f"Take the {props.LABELS[key].lower()} from this object's world location")
    if kind == "transform":
        ann["source_object"] = bpy.props.PointerProperty(
            type=bpy.types.Object, name="Object", update=on_edit,
            description="Take translate, rotate and scale from this object (e.g. an Empty)")
    attrs = {"bl_idname": idname(kind), "bl_label": LABEL[kind], "bl_icon": ICON[kind], "kind": kind,
             "__annotations__": ann, "__doc__": f"BlobTree {LABEL[kind].lower()}"}
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
    kind = "output"

    def init(self, context):
        new_input(self, "Model")

    def draw_props(self, context, layout):
        tree = self.id_data
        layout.prop(tree, "iso")
        layout.prop(tree, "preview_resolution")


classes = (*PRIMITIVE_CLASSES, *OPERATOR_CLASSES, *WARP_CLASSES, BlobTreeOutputNode)
BY_KIND = {c.kind: c for c in classes}
