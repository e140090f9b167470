"""The tone marks' quality: every bundled example in every preset look, measured against
the exact surface (bench/inkmeasure.py; definitions in bench/README.md).

    python bench/quality.py [--models all|heart,shell,...] [--looks all|hatched,...]
                            [--res 256] [--seed 0] [--out DIR]

Each model is seen from the command line's three-quarter view, lit by its default sun,
and framed as the command line cuts its picture (about the visible outlines, 1024 px).
The outlines are traced once per model; each look then places its strokes beside them
(as Place Strokes does). Per drawing it prints the marks' figures and the seconds the
strokes took; with --out it writes DIR/MODEL-LOOK.png (the whole drawing rasterised)
and DIR/MODEL-tone.png (the target tone).
"""
import argparse
import math
import os
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "tools"))
import pure  # noqa: E402

pure.install()
import numpy as np  # noqa: E402
from blobtree_ink.cli.render_args import CliError, floats  # noqa: E402

import inkmeasure as IM  # noqa: E402
import inkview as IV  # noqa: E402
from blobtree_ink import pipeline as PL  # noqa: E402
from blobtree_ink.blackboard.view import View  # noqa: E402
from blobtree_ink.model import Evaluator, load  # noqa: E402
from blobtree_ink.strokes import tone as TN  # noqa: E402
from blobtree_ink.strokes.style import STYLES, style  # noqa: E402

EXAMPLES = os.path.join(HERE, "..", "examples")
MODELS = ("sphere", "two_spheres", "torus", "csg_difference", "csg_union", "pear", "jug", "heart", "shell", "train")


def outlines_of(ev, eye, light, seed):
    job = PL.Job(ev, view=View(eye=eye), light=tuple(light), style=style("outlines"), seed=seed)
    res = PL.Illustration(job).run()
    return [s for name in IM.OUTLINE_LAYERS for s in res.strokes.layers.get(name, ())]


def drawing(ev, eye, light, st, lines, seed):
    """The look's strokes by layer, the hatching's split into its first and crossing
    layers, and the seconds the strokes took."""
    job = PL.Job(ev, view=View(eye=eye), light=tuple(light), style=st, requests=(PL.Request(PL.PLACE_STROKES),),
                 seed=seed, lines=tuple(lines))
    ill = PL.Illustration(job)
    first = None
    t = time.perf_counter()
    while ill.step():
        if first is None and ill.stage == "cross-hatching":
            first = len(ill.layers.get("Hatching", ()))
    seconds = time.perf_counter() - t
    layers = {k: list(v) for k, v in ill.result().strokes.layers.items()}
    hatch = layers.get("Hatching", [])
    split = len(hatch) if first is None else first
    return layers, (hatch[:split], hatch[split:]), seconds


def measure(ev, cam, lit, eye, st, layers, hatch, res, lines):
    mask = np.isfinite(lit)
    target = np.where(mask, TN.tone(np.nan_to_num(lit), st.shade_lower, st.shade_upper, st.contrast), 0.0)
    tone_strokes = [s for name in IM.TONE_LAYERS for s in layers.get(name, ())]
    ink = IV.downsample(IV.rasterise(cam, tone_strokes, res * 4), res)
    out = IM.tone_figures(target, ink, mask, res)
    out.update(IM.dot_figures(cam, layers.get("Stipples", [])))
    first, crossing = hatch
    fields = [(first, st.hatch_field, st.hatch_axis)]
    if crossing:
        fields.append((crossing, st.cross_field, st.hatch_axis))
    out.update(IM.hatch_figures(ev, cam, fields, eye) if first else {"along": math.nan, "ends": 0})
    out.update(IM.crossing_figures(ev, cam, tone_strokes, lines))
    out["strokes"] = len(tone_strokes)
    return out, target


COLUMNS = (("strokes", "{:>7d}"), ("tone_r", "{:>7.3f}"), ("evenness", "{:>8.3f}"), ("mean_tone", "{:>9.3f}"),
           ("mean_ink", "{:>8.3f}"), ("nn_cv", "{:>6.3f}"), ("touching", "{:>8.3f}"), ("along", "{:>6.3f}"),
           ("ends", "{:>5d}"), ("outside", "{:>7d}"), ("crossing", "{:>8d}"), ("seconds", "{:>7.2f}"))


def row(model, look, figures):
    cells = []
    for name, fmt in COLUMNS:
        v = figures.get(name, math.nan)
        cells.append(" " * (len(fmt.format(0 if "d" in fmt else 0.0)) - 1) + "-"
                     if v is None or (isinstance(v, float) and math.isnan(v)) else fmt.format(v))
    return f"{model:<15}{look:<19}" + " ".join(cells)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--models", default="all")
    ap.add_argument("--looks", default="all")
    ap.add_argument("--res", type=int, default=256, help="the target's and the tone figures' picture size")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--out", default=None, help="a folder for the pictures")
    ap.add_argument("--azimuth", type=float, default=None, help="the eye's degrees from the front (-y) towards +x")
    ap.add_argument("--elevation", type=float, default=None, help="the eye's degrees up")
    ap.add_argument("--light", default=None, help="x,y,z towards the sun (default: the viewer's upper left)")
    a = ap.parse_args(argv)
    try:
        light = None if a.light is None else np.array(floats(a.light, "--light"))
    except CliError as e:
        ap.error(str(e))
    if light is not None and not light.any():
        ap.error(f"--light: the light direction must not be zero, got {a.light!r}")
    view = {k: v for k, v in (("azimuth", a.azimuth), ("elevation", a.elevation)) if v is not None}
    models = MODELS if a.models == "all" else tuple(a.models.split(","))
    looks = tuple(k for k in STYLES if k != "outlines") if a.looks == "all" else tuple(a.looks.split(","))
    if a.out:
        os.makedirs(a.out, exist_ok=True)
    print(f"{'model':<15}{'look':<19}" + " ".join(f"{n:>{len(f.format(0 if 'd' in f else 0.0))}}"
                                                     for n, f in COLUMNS))
    for name in models:
        ev = Evaluator(load(os.path.join(EXAMPLES, f"{name}.json")))
        centre, radius = PL.bounds(ev)
        eye = PL.three_quarter_eye(centre, radius, **view)
        lit_from = PL.default_light(centre, eye) if light is None else light / np.linalg.norm(light)
        lines = outlines_of(ev, eye, lit_from, a.seed)
        cam = IV.Camera.framing(eye, centre, np.concatenate([s.points for s in lines]), 1024)
        lit, _ = IV.cast_light(ev, cam, lit_from, a.res)
        for look in looks:
            st = style(look)
            layers, hatch, seconds = drawing(ev, eye, lit_from, st, lines, a.seed)
            figures, target = measure(ev, cam, lit, eye, st, layers, hatch, a.res, lines)
            figures["seconds"] = seconds
            print(row(name, look, figures), flush=True)
            if a.out:
                every = lines + [s for v in layers.values() for s in v]
                IV.write_png(os.path.join(a.out, f"{name}-{look}.png"), 1.0 - IV.rasterise(cam, every, 1024))
                IV.write_png(os.path.join(a.out, f"{name}-{look}-tone.png"),
                             1.0 - np.kron(target, np.ones((1024 // a.res,) * 2)))


if __name__ == "__main__":
    main()
