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

from ..strokes.data import LAYERS, STROKE_LAYERS, Stroke
from . import compat, views

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
    """The model's Grease Pencil object (created once, then reused, drawn in front in
    the viewport), with its materials and layers; with ``collection``, in that collection
    and no other (a new object without one goes to the scene's)."""
    obj = bpy.data.objects.get(name)
    if obj is not None and obj.type != "GREASEPENCIL":
        raise ValueError(f"an object named '{name}' exists and is not Grease Pencil")
    if obj is None:
        gp = compat.grease_pencil_data().new(name)
        obj = bpy.data.objects.new(name, gp)
        # in front of the preview mesh in the viewport: the ink lies on the exact surface,
        # which the rough preview mesh cuts through (its hidden lines are removed already)
        obj.show_in_front = True
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
    """Write a pipeline Result on ``frame``: its owned layers replaced (the stroke layers'
    strokes in its region only, when it has one), its appended ones added to, the others
    untouched; the layers written remember the eye and the model they were drawn for
    (grease_pencil.views)."""
    for name in result.owned:
        region = result.region if name in STROKE_LAYERS else None
        write_layer(obj, name, result.strokes.layers.get(name, []), frame,
                    keep=None if region is None else lambda P, r=region: ~r.contains(P))
    for name in result.appended:
        write_layer(obj, name, result.strokes.layers.get(name, []), frame, keep=lambda P: np.ones(len(P), bool))
    whole = [n for n in result.owned if result.region is None or n not in STROKE_LAYERS]
    made = dict(model=result.model, made=result.made, hiders=result.hiders)
    views.record(obj, whole, frame, result.eye, result.centre, **made)
    views.record(obj, [n for n in result.owned if n not in whole], frame, result.eye, result.centre, result.region,
                 **made)
    views.record(obj, result.appended, frame, result.eye, result.centre, region=True, **made)
    return obj


def write_set(obj, stroke_set, frame=1):
    """Replace every layer of a StrokeSet on ``frame`` with its strokes."""
    for name, strokes in stroke_set.layers.items():
        write_layer(obj, name, strokes, frame)
    return obj


def read_layer(obj, name, frame):
    """The strokes of layer ``name``'s drawing shown on ``frame`` as plain strokes
    (strokes.data.Stroke, in the object's coordinates): what :func:`write_layer` wrote."""
    key = views.shown_frame(obj.data.layers[name], frame)
    n = len(key.drawing.strokes) if key is not None else 0
    if not n:
        return []
    drawing = key.drawing
    off = np.zeros(n + 1, np.int32)
    drawing.curve_offsets.foreach_get("value", off)
    k = int(off[-1])
    P = _values(drawing, "position", k, np.float32, 3).reshape(-1, 3).astype(float)
    r, o = _values(drawing, "radius", k, np.float32).astype(float), _values(drawing, "opacity", k, np.float32, 1, 1)
    cyclic, mat = _values(drawing, "cyclic", n, bool), _values(drawing, "material_index", n, np.int32)
    mats = [m.name if m is not None else "" for m in obj.data.materials]
    dots_i = mats.index(DOTS_MATERIAL) if DOTS_MATERIAL in mats else -1
    return [Stroke(P[a:b], r[a:b], o[a:b].astype(float), cyclic=bool(c), dots=bool(m == dots_i))
            for a, b, c, m in zip(off[:-1], off[1:], cyclic, mat)]


def _values(drawing, name, n, dtype, width=1, default=0):
    """An attribute's values as a flat array (``default`` where the drawing has none)."""
    attr = drawing.attributes.get(name)
    out = np.full(n * width, default, dtype)
    if attr is not None and n:
        attr.data.foreach_get("vector" if width == 3 else "value", out)
    return out


def _attribute(drawing, name, kind, domain):
    return drawing.attributes.get(name) or drawing.attributes.new(name, kind, domain)


def write_layer(obj, name, strokes, frame=1, keep=None):
    """The drawing of layer ``name`` on ``frame`` gets these strokes. Its strokes are
    removed first, all of them, or with ``keep`` (points (k, 3) -> which to keep, per
    point) those with a point not kept; the strokes that stay are not touched."""
    gp = obj.data
    mats = [m.name if m is not None else "" for m in gp.materials]
    line_i, dots_i = mats.index(LINE_MATERIAL), mats.index(DOTS_MATERIAL)
    drawing = _frame(gp.layers[name], frame).drawing
    n = len(drawing.strokes)
    if n:
        if keep is None:
            drawing.remove_strokes()
        else:
            off = np.zeros(n + 1, np.int32)
            drawing.curve_offsets.foreach_get("value", off)
            ok = keep(_values(drawing, "position", int(off[-1]), np.float32, 3).reshape(-1, 3)).astype(np.int64)
            whole = np.add.reduceat(ok, off[:-1]) == np.diff(off) if off[-1] else np.ones(n, bool)
            gone = np.flatnonzero(~whole)
            if len(gone):
                drawing.remove_strokes(indices=gone.tolist())
    if strokes:
        c0 = len(drawing.strokes)
        p0 = len(drawing.attributes["position"].data) if c0 else 0
        drawing.add_strokes([len(s.points) for s in strokes])
        p1, c1 = len(drawing.attributes["position"].data), len(drawing.strokes)
        for attr, kind, domain, width, dtype, new in (
                ("position", "FLOAT_VECTOR", "POINT", 3, np.float32,
                 np.concatenate([np.asarray(s.points, np.float32).reshape(-1, 3) for s in strokes])),
                ("radius", "FLOAT", "POINT", 1, np.float32, np.concatenate([s.radius for s in strokes])),
                ("opacity", "FLOAT", "POINT", 1, np.float32, np.concatenate([s.opacity for s in strokes])),
                ("cyclic", "BOOLEAN", "CURVE", 1, bool, [bool(s.cyclic) for s in strokes]),
                ("material_index", "INT", "CURVE", 1, np.int32, [dots_i if s.dots else line_i for s in strokes])):
            total, first = (p1, p0) if domain == "POINT" else (c1, c0)
            a = _attribute(drawing, attr, kind, domain)
            values = _values(drawing, attr, total, dtype, width, default=1 if attr == "opacity" else 0)
            values[first * width:] = np.asarray(new, dtype).ravel()
            a.data.foreach_set("vector" if width == 3 else "value", values)
        drawing.tag_positions_changed()
    obj.data.update_tag()
