"""The `render` command's Blender side (its options are parsed by cli.render_args): a
factory-empty scene with a camera framing the model and a sun towards the light, the
job built from that scene as the operators build theirs (operators.jobs), the pipeline
run to the end, the result written to a Grease Pencil object, then DIR/NAME.png, .svg
and .blend (grease_pencil.render)."""
import os
import re
import time

import bpy

from .. import pipeline as PL
from ..agents import Settings
from ..cli.render_args import CliError
from ..grease_pencil import render as OUT
from ..grease_pencil import scene as S
from ..grease_pencil.writer import ink_object, write
from ..model import Evaluator, ModelError, load
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
    settings = Settings(resolution=spec.grid, agents=spec.agents, seed=spec.seed)
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
    paths = {ext: os.path.join(out_dir, f"{name}.{ext}") for ext in ("png", "blend", "svg")}
    nudge = OUT.sideways(eye, centre, 0.01 * ill.line_radius)
    try:
        os.makedirs(out_dir, exist_ok=True)
        OUT.atomic(paths["png"], lambda tmp: OUT.render_png(sc, tmp))
        OUT.atomic(paths["svg"], lambda tmp: OUT.export_svg(obj, tmp, result.strokes.layers["Stipples"],
                                                             sc.frame_current, nudge))
        OUT.atomic(paths["blend"], OUT.save_blend)
    except OSError as e:
        raise CliError(f"cannot write to {out_dir}: {e.strerror or e}") from None
    except (OUT.OutputError, RuntimeError) as e:     # RuntimeError: what Blender's operators raise
        raise CliError(f"Blender could not write the outputs: {e}") from None
    log("strokes: " + ", ".join(f"{k} {len(v)}" for k, v in result.strokes.layers.items() if v) +
        f"; wrote {', '.join(paths.values())} ({time.perf_counter() - t0:.1f} s)")
    return 0
