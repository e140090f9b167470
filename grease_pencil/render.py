"""Illustrate a model and write DIR/NAME.png, DIR/NAME.blend and DIR/NAME.svg.

The pure pipeline (MASSRIS outlines, hidden-line removal against the exact surface,
plain stroke data) feeds the Grease Pencil writer; Blender renders the PNG (Workbench,
white paper), saves the .blend and exports the SVG with its own Grease Pencil exporter.
Every output is written to a temporary name in DIR and renamed into place, so a failed
or interrupted run never leaves a half-written file or replaces a good one.
"""
import os
import re
import time

import bpy
import numpy as np

from ..agents import Session, Settings
from ..blackboard.polygonise import surface_box
from ..blackboard.view import View
from ..model import Evaluator
from ..strokes import style as ST
from . import svg
from . import scene as S
from .writer import ink_object, write


class RenderError(Exception):
    """A user-facing failure of the render (bad options, nothing to draw)."""


def plan_view(ev, azimuth=35.0, elevation=25.0):
    box = surface_box(ev)
    if box is None:
        raise RenderError("the model has no surface to draw (its field never reaches iso)")
    lo, hi = box
    centre = 0.5 * (lo + hi)
    radius = 0.5 * float(np.linalg.norm(hi - lo))
    return centre, radius, S.three_quarter_eye(centre, radius, azimuth, elevation)


def illustrate(model, out_dir, size=1024, grid=20, agents=Settings.agents, seed=0, azimuth=35.0, elevation=25.0,
               seconds=None, style=None, light=None, log=print):
    """Illustrate ``model`` with ``style`` (a strokes.style.Style; default outlines)
    lit from ``light`` (a direction; default upper left of the viewer)."""
    style = style or ST.Style()
    try:
        style.check()
    except ValueError as e:
        raise RenderError(f"style: {e}") from None
    if not os.path.isdir(out_dir):
        parent = os.path.dirname(os.path.abspath(out_dir))
        if not os.path.isdir(parent):
            raise RenderError(f"output directory {out_dir} does not exist (nor does its parent)")
        os.mkdir(out_dir)
    if not (64 <= size <= 8192):
        raise RenderError(f"--size must be from 64 to 8192 pixels, got {size}")
    name = re.sub(r"[^A-Za-z0-9_.-]+", "_", model.name) or "model"
    t0 = time.perf_counter()
    ev = Evaluator(model)
    centre, radius, eye = plan_view(ev, azimuth, elevation)
    try:
        session = Session(ev, View(eye=eye), Settings(resolution=grid, agents=agents, seed=seed))
    except ValueError as e:
        raise RenderError(str(e)) from None
    session.request("OUTLINES")
    session.run(seconds=seconds)
    prog = session.progress()
    log(f"outlines: {prog['outlines']} after {prog['iterations']} iterations, "
        f"length {prog['outline_length']:.3g} ({time.perf_counter() - t0:.1f} s)")
    view_width = 2 * np.linalg.norm(eye - centre) * 18.0 / 50.0
    line_radius = 1.1 * view_width / size
    light = ST.default_light(centre, eye) if light is None else _direction(light)
    strokes = ST.place(session, eye, light, style, np.random.default_rng(seed), line_radius)
    if strokes.count() == 0:
        raise RenderError("no visible outline was found to draw")
    bpy.ops.wm.read_homefile(use_empty=True, use_factory_startup=True)
    sc = bpy.context.scene
    obj = ink_object(f"{model.name} Ink")
    write(obj, strokes, frame=sc.frame_current)
    S.setup(sc, centre, eye, size=size, light_dir=light)
    paths = {ext: os.path.join(out_dir, f"{name}.{ext}") for ext in ("png", "blend", "svg")}
    _atomic(paths["png"], lambda tmp: _render_png(sc, tmp, obj))
    _atomic(paths["svg"], lambda tmp: _export_svg(obj, tmp, strokes, sc, 1e-3 * line_radius * (eye - centre)))
    _atomic(paths["blend"], lambda tmp: bpy.ops.wm.save_as_mainfile(filepath=tmp, copy=True, check_existing=False))
    log(f"strokes: " + ", ".join(f"{k} {len(v)}" for k, v in strokes.layers.items() if v) +
        f"; wrote {', '.join(paths.values())} ({time.perf_counter() - t0:.1f} s)")
    return paths, strokes, session


def _direction(v):
    v = np.asarray(v, float)
    if v.shape != (3,) or not np.all(np.isfinite(v)) or not np.linalg.norm(v) > 0:
        raise RenderError(f"the light direction must be three finite numbers, not all zero, got {v.tolist()}")
    return v / np.linalg.norm(v)


def _atomic(path, write_fn):
    d, base = os.path.split(path)
    stem, ext = os.path.splitext(base)
    tmp = os.path.join(d, f".{stem}.partial{ext}")
    try:
        write_fn(tmp)
        if not os.path.exists(tmp):
            raise RenderError(f"Blender did not write {tmp}")
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)


def _render_png(sc, tmp, obj):
    """Render the PNG. Blender 5.2's renderer draws nothing for a DOTS material (seen in
    Workbench, background mode) while a LINE material draws a one-point stroke as a
    round dot in every version, so the stipples' material is drawn as LINE for the
    render and set back to DOTS for the saved file."""
    dots = [m.grease_pencil for m in obj.data.materials if m is not None and m.grease_pencil.mode == "DOTS"]
    for gpm in dots:
        gpm.mode = "LINE"
    try:
        sc.render.filepath = tmp
        bpy.ops.render.render(write_still=True)
    finally:
        for gpm in dots:
            gpm.mode = "DOTS"


def _export_svg(obj, tmp, strokes, sc, nudge):
    dots = strokes.count("Stipples")
    if dots:          # the exporter drops one-point strokes: give it two-point ones for now
        write(obj, svg.with_exportable_dots(strokes, np.cross(nudge, [0.0, 0.0, 1.0])), frame=sc.frame_current)
    try:
        _export(obj, tmp)
    finally:
        if dots:
            write(obj, strokes, frame=sc.frame_current)
    if dots:
        n = svg.dots_to_circles(tmp)
        if n != dots:
            raise RenderError(f"the SVG export kept {n} of {dots} stipples")


def _export(obj, tmp):
    for o in bpy.context.view_layer.objects:
        o.select_set(o == obj)
    bpy.context.view_layer.objects.active = obj
    res = bpy.ops.wm.grease_pencil_export_svg(filepath=tmp, selected_object_type="ACTIVE", use_fill=False,
                                              use_uniform_width=True, use_clip_camera=True)
    if res != {"FINISHED"}:
        raise RenderError(f"Grease Pencil SVG export failed: {res}")
