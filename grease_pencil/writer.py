"""Write the pipeline's plain strokes (pipeline.Result, strokes.StrokeSet) to a Grease
Pencil object, in bulk.

One Grease Pencil object per illustrated model, a layer per kind (strokes.data.LAYERS).
A result replaces the drawings of the layers it owns on the frame as a whole, adds its
strokes to the drawings of the layers it appends to, and leaves every other layer as
it is, so that requests build a drawing up. Strokes go in with ``add_strokes`` once
with every stroke's size, then ``foreach_set`` on position, radius, opacity, cyclic and
material_index; never point by point. Lines use a LINE material, stipples (one-point
strokes) a DOTS material set up to draw in this Blender (grease_pencil.compat).
"""
import bpy
import numpy as np

from ..strokes.data import LAYERS
from . import compat

INK = (0.02, 0.02, 0.03, 1.0)
LINE_MATERIAL = "BlobTree Ink Line"
DOTS_MATERIAL = "BlobTree Ink Dots"


def _material(name, dots):
    mat = bpy.data.materials.get(name)
    if mat is None:
        mat = bpy.data.materials.new(name)
    if mat.grease_pencil is None:
        bpy.data.materials.create_gpencil_data(mat)
    if dots:
        compat.stipple_style(mat.grease_pencil)
    else:
        mat.grease_pencil.mode = "LINE"
    mat.grease_pencil.color = INK
    mat.grease_pencil.show_fill = False
    mat.grease_pencil.show_stroke = True
    return mat


def ink_object(name, collection=None):
    """The model's Grease Pencil object (created once, then reused), with its materials
    and layers; with ``collection``, in that collection and no other (a new object
    without one goes to the scene's)."""
    obj = bpy.data.objects.get(name)
    if obj is not None and obj.type != "GREASEPENCIL":
        raise ValueError(f"an object named '{name}' exists and is not Grease Pencil")
    if obj is None:
        gp = compat.grease_pencil_data().new(name)
        obj = bpy.data.objects.new(name, gp)
        (collection or bpy.context.scene.collection).objects.link(obj)
    elif collection is not None:
        if collection.name not in [c.name for c in obj.users_collection]:
            collection.objects.link(obj)
        for other in list(obj.users_collection):
            if other.name != collection.name:
                other.objects.unlink(obj)
    gp = obj.data
    for mat in (_material(LINE_MATERIAL, False), _material(DOTS_MATERIAL, True)):
        if mat.name not in [m.name for m in gp.materials if m is not None]:
            gp.materials.append(mat)
    for layer in LAYERS:
        if gp.layers.get(layer) is None:
            gp.layers.new(layer)
    return obj


def stroke_count(obj, layers, frame):
    """Strokes on the given layers of a Grease Pencil object (None: 0) on a frame."""
    if obj is None or obj.type != "GREASEPENCIL":
        return 0
    n = 0
    for name in layers:
        layer = obj.data.layers.get(name)
        for fr in (layer.frames if layer is not None else []):
            if fr.frame_number == frame:
                n += len(fr.drawing.strokes)
    return n


def _frame(layer, number):
    for fr in layer.frames:
        if fr.frame_number == number:
            return fr
    return layer.frames.new(number)


def write(obj, result, frame=1):
    """Write a pipeline Result on ``frame``: its owned layers replaced, its appended ones
    added to, the others untouched."""
    for name in result.owned:
        write_layer(obj, name, result.strokes.layers.get(name, []), frame)
    for name in result.appended:
        write_layer(obj, name, result.strokes.layers.get(name, []), frame, append=True)
    return obj


def write_set(obj, stroke_set, frame=1):
    """Replace every layer of a StrokeSet on ``frame`` with its strokes."""
    for name, strokes in stroke_set.layers.items():
        write_layer(obj, name, strokes, frame)
    return obj


def _read(drawing, name, n, dtype, width=1, default=0):
    """An attribute's values as a flat array (``default`` where the drawing has none)."""
    attr = drawing.attributes.get(name)
    out = np.full(n * width, default, dtype)
    if attr is not None and n:
        attr.data.foreach_get("vector" if width == 3 else "value", out)
    return out


def write_layer(obj, name, strokes, frame=1, append=False):
    """The drawing of layer ``name`` on ``frame`` becomes these strokes (with ``append``:
    the strokes it has, then these)."""
    gp = obj.data
    mats = [m.name if m is not None else "" for m in gp.materials]
    line_i, dots_i = mats.index(LINE_MATERIAL), mats.index(DOTS_MATERIAL)
    drawing = _frame(gp.layers[name], frame).drawing
    keep = {}
    if append and len(drawing.strokes):
        npts = len(drawing.attributes["position"].data)
        ncurves = len(drawing.strokes)
        keep = {"position": _read(drawing, "position", npts, np.float32, 3),
                "radius": _read(drawing, "radius", npts, np.float32),
                "opacity": _read(drawing, "opacity", npts, np.float32, default=1),
                "cyclic": _read(drawing, "cyclic", ncurves, bool),
                "material_index": _read(drawing, "material_index", ncurves, np.int32),
                "sizes": [len(s.points) for s in drawing.strokes]}
    if len(drawing.strokes):
        drawing.remove_strokes()
    if not strokes and not keep:
        obj.data.update_tag()
        return
    sizes = keep.get("sizes", []) + [len(s.points) for s in strokes]
    drawing.add_strokes(sizes)

    def cat(old, new, dtype):
        parts = ([old] if old is not None else []) + ([np.asarray(new, dtype)] if len(new) else [])
        return np.concatenate(parts) if parts else np.zeros(0, dtype)
    pos = cat(keep.get("position"), np.concatenate([np.asarray(s.points, np.float32).ravel() for s in strokes])
              if strokes else [], np.float32)
    drawing.attributes["position"].data.foreach_set("vector", pos)
    for attr, values in (("radius", [s.radius for s in strokes]), ("opacity", [s.opacity for s in strokes])):
        a = drawing.attributes.get(attr) or drawing.attributes.new(attr, "FLOAT", "POINT")
        a.data.foreach_set("value", cat(keep.get(attr), np.concatenate(values) if values else [], np.float32))
    cyc = drawing.attributes.get("cyclic") or drawing.attributes.new("cyclic", "BOOLEAN", "CURVE")
    cyc.data.foreach_set("value", cat(keep.get("cyclic"), [bool(s.cyclic) for s in strokes], bool))
    mi = drawing.attributes.get("material_index") or drawing.attributes.new("material_index", "INT", "CURVE")
    mi.data.foreach_set("value", cat(keep.get("material_index"), [dots_i if s.dots else line_i for s in strokes],
                                     np.int32))
    drawing.tag_positions_changed()
    obj.data.update_tag()
