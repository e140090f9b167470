"""Write plain stroke data (strokes.StrokeSet) to a Grease Pencil object, in bulk.

One Grease Pencil object per illustrated model, a layer per kind (Silhouette, Crease,
Curvature, Hatching, Stipples, Strokes). Each layer's drawing on the frame is replaced
as a whole: ``add_strokes`` once with every stroke's size, then ``foreach_set`` on
position, radius, opacity, cyclic and material_index; never point by point. Lines use
a LINE material, stipples (one-point strokes) a DOTS material.
"""
import bpy
import numpy as np

from ..strokes.data import LAYERS
from .compat import grease_pencil_data

INK = (0.02, 0.02, 0.03, 1.0)
LINE_MATERIAL = "BlobTree Ink Line"
DOTS_MATERIAL = "BlobTree Ink Dots"


def _material(name, mode):
    mat = bpy.data.materials.get(name)
    if mat is None:
        mat = bpy.data.materials.new(name)
    if mat.grease_pencil is None:
        bpy.data.materials.create_gpencil_data(mat)
    mat.grease_pencil.mode = mode
    mat.grease_pencil.color = INK
    mat.grease_pencil.show_fill = False
    mat.grease_pencil.show_stroke = True
    return mat


def ink_object(name, collection=None):
    """The model's Grease Pencil object (created once, then reused)."""
    obj = bpy.data.objects.get(name)
    if obj is not None and obj.type != "GREASEPENCIL":
        raise ValueError(f"an object named '{name}' exists and is not Grease Pencil")
    if obj is None:
        gp = grease_pencil_data().new(name)
        obj = bpy.data.objects.new(name, gp)
        (collection or bpy.context.scene.collection).objects.link(obj)
    gp = obj.data
    for mat in (_material(LINE_MATERIAL, "LINE"), _material(DOTS_MATERIAL, "DOTS")):
        if mat.name not in [m.name for m in gp.materials if m is not None]:
            gp.materials.append(mat)
    for layer in LAYERS:
        if gp.layers.get(layer) is None:
            gp.layers.new(layer)
    return obj


def _frame(layer, number):
    for fr in layer.frames:
        if fr.frame_number == number:
            return fr
    return layer.frames.new(number)


def write(obj, stroke_set, frame=1):
    """Replace the drawings of every layer on ``frame`` with the stroke set's strokes."""
    gp = obj.data
    mats = [m.name if m is not None else "" for m in gp.materials]
    line_i, dots_i = mats.index(LINE_MATERIAL), mats.index(DOTS_MATERIAL)
    for name, strokes in stroke_set.layers.items():
        drawing = _frame(gp.layers[name], frame).drawing
        if len(drawing.strokes):
            drawing.remove_strokes()
        if not strokes:
            continue
        sizes = [len(s.points) for s in strokes]
        drawing.add_strokes(sizes)
        pos = np.concatenate([np.asarray(s.points, np.float32) for s in strokes])
        drawing.attributes["position"].data.foreach_set("vector", pos.ravel())
        for attr, values in (("radius", [s.radius for s in strokes]), ("opacity", [s.opacity for s in strokes])):
            a = drawing.attributes.get(attr) or drawing.attributes.new(attr, "FLOAT", "POINT")
            a.data.foreach_set("value", np.concatenate(values).astype(np.float32))
        cyc = drawing.attributes.get("cyclic") or drawing.attributes.new("cyclic", "BOOLEAN", "CURVE")
        cyc.data.foreach_set("value", [bool(s.cyclic) for s in strokes])
        mi = drawing.attributes.get("material_index") or drawing.attributes.new("material_index", "INT", "CURVE")
        mi.data.foreach_set("value", [dots_i if s.dots else line_i for s in strokes])
        drawing.tag_positions_changed()
    obj.data.update_tag()
    return obj
