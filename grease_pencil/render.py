"""The command line's outputs from a scene holding an illustration: DIR/NAME.png
(rendered), DIR/NAME.svg (Blender's Grease Pencil SVG exporter, stipples completed as
circles: grease_pencil.svg) and DIR/NAME.blend. Every output is written to a temporary
name in DIR and renamed into place, so a failed or interrupted run never leaves a
half-written file or replaces a good one."""
import os

import bpy
import numpy as np

from ..model.vectors import cross
from . import svg
from .writer import write_layer


class OutputError(Exception):
    """An output Blender did not write, or wrote short."""


def atomic(path, write_fn):
    """Write ``path`` through ``write_fn(tmp)`` and rename it into place."""
    d, base = os.path.split(path)
    stem, ext = os.path.splitext(base)
    tmp = os.path.join(d, f".{stem}.partial{ext}")
    try:
        write_fn(tmp)
        if not os.path.exists(tmp):
            raise OutputError(f"Blender did not write {tmp}")
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)


def render_png(scene, tmp):
    scene.render.filepath = tmp
    bpy.ops.render.render(write_still=True)


def save_blend(tmp):
    bpy.ops.wm.save_as_mainfile(filepath=tmp, copy=True, check_existing=False)


def export_svg(obj, tmp, stipples, frame, nudge):
    """Export the object's drawing as SVG. The exporter drops one-point strokes: the
    stipples (the Stipples layer's strokes, ``stipples``) are written as two-point
    strokes ``nudge`` long for the export, replaced by circles in the file, and written
    back as they were."""
    if stipples:
        write_layer(obj, "Stipples", svg.exportable_dots(stipples, nudge), frame)
    try:
        for o in bpy.context.view_layer.objects:
            o.select_set(o == obj)
        bpy.context.view_layer.objects.active = obj
        res = bpy.ops.wm.grease_pencil_export_svg(filepath=tmp, selected_object_type="ACTIVE", use_fill=False,
                                                  use_uniform_width=True, use_clip_camera=True)
        if res != {"FINISHED"}:
            raise OutputError(f"Grease Pencil SVG export failed: {res}")
    finally:
        if stipples:
            write_layer(obj, "Stipples", stipples, frame)
    if stipples:
        n = svg.dots_to_circles(tmp)
        if n != len(stipples):
            raise OutputError(f"the SVG export kept {n} of {len(stipples)} stipples")


def sideways(eye, centre, length):
    """A short step across the view (for a two-point stand-in of a dot)."""
    d = cross(np.asarray(eye, float) - np.asarray(centre, float), [0.0, 0.0, 1.0])
    n = np.linalg.norm(d)
    return (d / n if n > 0 else np.array([1.0, 0.0, 0.0])) * length
