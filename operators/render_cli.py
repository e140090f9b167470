"""The `render` command's Blender side (its options are parsed by cli.render_args).

A JSON model: a factory-empty scene with a camera framing the model and a sun towards
the light, the job built from that scene as the operators build theirs
(operators.jobs), the pipeline run to the end, the result written to a Grease Pencil
object, then DIR/NAME.png, .svg and .blend (grease_pencil.render).

A .blend scene's tree: the scene opened as saved, then frame by frame the tree
illustrated as the bake does (operators.frames: its camera, lights, animation and
settings at that frame), each frame rendered to DIR/NAME_####.png and exported to
DIR/NAME_####.svg, with a progress line; at the end the scene with its drawings saved
as DIR/NAME.blend."""
import os
import re
import time

import bpy

import numpy as np

from .. import pipeline as PL
from ..agents import Settings
from ..blobtree_nodes.animation import DriverError
from ..blobtree_nodes.compile import TreeError
from ..blobtree_nodes.idnames import TREE
from ..cli.render_args import CliError
from ..grease_pencil import render as OUT
from ..grease_pencil import scene as S
from ..grease_pencil.writer import ink_object, write
from ..model import Evaluator, ModelError, load
from . import frames as FR
from . import jobs


def requests_of(style):
    """The requests a style asks of the command line: its outlines and its strokes."""
    out = []
    if style.outlines:
        out.append(PL.Request(PL.OUTLINES))
    if style.stroke_switches():
        out.append(PL.Request(PL.PLACE_STROKES))
    if not out:
        raise CliError("the style draws nothing: give it outlines or some strokes (--requests)")
    return out


def render(spec, log):
    """Illustrate spec.model and write the outputs; returns the exit status (CliError for
    what the user can mend)."""
    if spec.model.lower().endswith(".blend"):
        return render_scene(spec, log)
    try:
        model = load(spec.model)
    except ModelError as e:
        raise CliError(str(e)) from None
    requests = requests_of(spec.style)
    out_dir = spec.out
    parent = os.path.dirname(os.path.abspath(out_dir))
    if os.path.exists(out_dir) and not os.path.isdir(out_dir):
        raise CliError(f"output directory {out_dir} is a file")
    if not os.path.isdir(out_dir) and not os.path.isdir(parent):
        raise CliError(f"output directory {out_dir} does not exist (nor does its parent)")
    name = re.sub(r"[^A-Za-z0-9_.-]+", "_", model.name) or "model"
    t0 = time.perf_counter()
    ev = Evaluator(model)
    try:
        centre, radius = PL.bounds(ev)
    except PL.NothingToDraw as e:
        raise CliError(str(e)) from None
    eye = PL.three_quarter_eye(centre, radius, spec.azimuth, spec.elevation)
    light = PL.default_light(centre, eye) if spec.light is None else spec.light      # the sun of the scene
    bpy.ops.wm.read_homefile(use_empty=True, use_factory_startup=True)
    sc = bpy.context.scene
    S.setup(sc, centre, eye, size=spec.size, light_dir=light)
    settings = Settings(resolution=spec.grid, agents=spec.agents, seed=spec.seed, kinds=spec.lines)
    try:
        job = jobs.job(ev, sc, spec.style, settings, requests, spec.seed, seconds=spec.seconds)
        ill = PL.Illustration(job)
        result = ill.run()
    except PL.JobError as e:
        raise CliError(str(e)) from None
    pr = result.progress
    log(f"outlines: {pr.outlines} after {pr.iterations} iterations, length {pr.outline_length:.3g} "
        f"({time.perf_counter() - t0:.1f} s)")
    if result.strokes.count() == 0:
        raise CliError("nothing visible was found to draw")
    obj = ink_object(f"{model.name} Ink")
    write(obj, result, frame=sc.frame_current)
    try:
        S.crop_camera(sc, sc.camera, np.concatenate([s.points for ss in result.strokes.layers.values() for s in ss]))
    except ValueError as e:
        raise CliError(f"the picture cannot be cut about the drawing: {e}") from None
    paths = {ext: os.path.join(out_dir, f"{name}.{ext}") for ext in ("png", "blend", "svg")}
    try:
        os.makedirs(out_dir, exist_ok=True)
        OUT.atomic(paths["png"], lambda tmp: OUT.render_png(sc, tmp))
        OUT.atomic(paths["svg"], lambda tmp: OUT.export_svg(sc, obj, tmp, sc.frame_current))
        OUT.atomic(paths["blend"], OUT.save_blend)
    except OSError as e:
        raise CliError(f"cannot write to {out_dir}: {e.strerror or e}") from None
    except (OUT.OutputError, RuntimeError) as e:     # RuntimeError: what Blender's operators raise
        raise CliError(f"Blender could not write the outputs: {e}") from None
    log("strokes: " + ", ".join(f"{k} {len(v)}" for k, v in result.strokes.layers.items() if v) +
        f"; wrote {', '.join(paths.values())} ({time.perf_counter() - t0:.1f} s)")
    return 0


def _out_dir(out_dir):
    parent = os.path.dirname(os.path.abspath(out_dir))
    if os.path.exists(out_dir) and not os.path.isdir(out_dir):
        raise CliError(f"output directory {out_dir} is a file")
    if not os.path.isdir(out_dir) and not os.path.isdir(parent):
        raise CliError(f"output directory {out_dir} does not exist (nor does its parent)")


def render_scene(spec, log):
    """A scene's tree, frame by frame: DIR/NAME_####.png and .svg, then DIR/NAME.blend."""
    if not os.path.isfile(spec.model):
        raise CliError(f"{spec.model}: no such file")
    _out_dir(spec.out)
    try:
        bpy.ops.wm.open_mainfile(filepath=spec.model, load_ui=False)
    except RuntimeError as e:
        raise CliError(f"{spec.model}: cannot be opened as a Blender file ({e})") from None
    tree = bpy.data.node_groups.get(spec.tree)
    if tree is None or tree.bl_idname != TREE:
        names = ", ".join(t.name for t in bpy.data.node_groups if t.bl_idname == TREE) or "none"
        raise CliError(f"{spec.model}: no BlobTree named '{spec.tree}' (its BlobTrees: {names})")
    sc = bpy.context.scene
    if sc.camera is None:
        raise CliError(f"{spec.model}: the scene has no camera to illustrate and render from")
    if spec.size is not None:
        sc.render.resolution_x = sc.render.resolution_y = spec.size
        sc.render.resolution_percentage = 100
    sc.render.image_settings.file_format = "PNG"
    if tree.ink.paper:
        S.paper(sc)
    first, last = spec.frames if spec.frames is not None else (sc.frame_current,) * 2
    name = re.sub(r"[^A-Za-z0-9_.-]+", "_", tree.name) or "tree"
    followed = FR.followed_objects(tree)
    t0 = time.perf_counter()
    previous = None                   # each frame goes on from the last (pipeline.continuation)
    try:
        os.makedirs(spec.out, exist_ok=True)
        for frame in FR.frame_range(first, last):
            t = time.perf_counter()
            sc.frame_set(frame)
            tree = bpy.data.node_groups[spec.tree]
            FR.check_followed(tree, followed, frame)
            try:
                job, _ = FR.frame_job(tree, sc)
                ill = PL.Illustration(job, previous=previous, remember=True)
                result = ill.run()
                previous = ill.continuation()
            except (TreeError, DriverError, PL.JobError, PL.NothingToDraw) as e:
                raise CliError(f"frame {frame}: {e}") from None
            obj = FR.write_frame(tree, result, frame)
            stem = os.path.join(spec.out, f"{name}_{frame:04d}")
            OUT.atomic(stem + ".png", lambda tmp: OUT.render_png(sc, tmp))
            OUT.atomic(stem + ".svg", lambda tmp: OUT.export_svg(sc, obj, tmp, frame))
            pr = result.progress
            log(f"frame {frame}: {result.strokes.count()} strokes, {pr.outlines} outlines after {pr.iterations} "
                f"iterations; wrote {stem}.png, .svg ({time.perf_counter() - t:.1f} s)")
        blend = os.path.join(spec.out, f"{name}.blend")
        OUT.atomic(blend, OUT.save_blend)
    except FR.FrameError as e:
        raise CliError(str(e)) from None
    except OSError as e:
        raise CliError(f"cannot write to {spec.out}: {e.strerror or e}") from None
    except (OUT.OutputError, RuntimeError) as e:
        raise CliError(f"Blender could not write the outputs: {e}") from None
    log(f"frames {first}-{last}: wrote {blend} ({time.perf_counter() - t0:.1f} s in all)")
    return 0
