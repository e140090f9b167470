"""The command line's outputs from a scene holding an illustration: DIR/NAME.png
(rendered), DIR/NAME.svg (the drawing through the scene camera: grease_pencil.svg) and
DIR/NAME.blend. Every output is written to a temporary
name in DIR and renamed into place, so a failed or interrupted run never leaves a
half-written file or replaces a good one."""
import os
from dataclasses import replace

import bpy
import numpy as np

from . import svg
from .writer import INK, read_layer


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


def export_svg(scene, obj, tmp, frame):
    """Write the ink object's drawing shown on ``frame`` (its layers that render) as an
    SVG seen through the scene camera, on a page of the rendered picture's size
    (grease_pencil.svg): line on line with the PNG."""
    cam = scene.camera
    if cam is None or cam.type != "CAMERA":
        raise OutputError("the scene has no camera to draw the SVG through")
    M = np.array(obj.matrix_world, float)
    scale = float(np.cbrt(abs(np.linalg.det(M[:3, :3]))))          # a radius in the object, in the scene
    layers = {}
    for layer in obj.data.layers:
        if not layer.hide:
            layers[layer.name] = [replace(s, points=s.points @ M[:3, :3].T + M[:3, 3], radius=s.radius * scale)
                                  for s in read_layer(obj, layer.name, frame)]
    r = scene.render
    size = (r.resolution_x * r.resolution_percentage / 100, r.resolution_y * r.resolution_percentage / 100)
    try:
        svg.write(tmp, layers, lens(scene, cam), size, INK)
    except ValueError as e:
        raise OutputError(str(e)) from None


def lens(scene, cam):
    """The scene camera as the SVG's page sees through it (grease_pencil.svg.Lens): its
    frame as Blender makes it for the scene's render (sensor fit, aspect, lens shift)."""
    corners = np.array([tuple(v) for v in cam.data.view_frame(scene=scene)], float)
    ortho = cam.data.type == "ORTHO"
    depth = 1.0 if ortho else float(np.abs(corners[:, 2]).max())
    m = cam.matrix_world
    return svg.Lens(eye=np.array(m.translation, float), axes=np.array(m.to_3x3().normalized(), float),
                    centre=tuple(corners[:, :2].mean(axis=0) / depth),
                    half=tuple(0.5 * np.ptp(corners[:, :2], axis=0) / depth), ortho=ortho)
