"""Feature-outline coverage over time: MASSRIS against the WH particle baseline; or,
with --views, MASSRIS run to its end from views all round each model.

    python bench/outlines.py [--models heart,train,shell|all] [--gt-res 256] [--limit 60]
                             [--grid N] [--agents N] [--no-baseline] [--views N]

Ground truth: silhouette and crease points of a dense polygonisation (about --gt-res^3
cubic cells over the model), projected into a 1024-pixel image from a fixed three-quarter
view. A crease is a jump of the normal: a dense-mesh edge whose vertex normals differ
by more than the crease angle is only a candidate (a smooth but tight bend, like the
heart's veins, does that too); candidates are kept where narrowing the edge to 1e-8 of
the model's size still shows the jump. Each method runs in short slices, its own
initialisation included in its time: one system iteration of MASSRIS, about two seconds
of the baseline (a particle step and the traces it starts within that budget; shorter
budgets slow it down, each particle step costing the same). After each slice the fraction
of ground-truth pixels within 1 pixel of its traced outlines is measured (measuring is
not timed). Prints the time each method needs to reach 95 % and the ratio, and saves
the curves to bench/outlines.png.

--views N (8 or more) runs MASSRIS to its end (or --limit) from N views, azimuths 360/N
apart and elevations cycling through -30, 0, 30 and 60 degrees, at the distance of the
three-quarter view, and prints per view its coverage, precision, gaps, dangling ends and
seconds, then each model's worst (bench/README.md says what each means).

--turning N runs N frames of an eye turning --turn degrees a frame about each model
(from the three-quarter view, at its elevation): each frame once going on from the last
frame's session (agents.continuation) and once from scratch, both to their end, and
prints per frame after the first how far they agree (the share of each one's outline
pixels within 1 pixel of the other's), each one's coverage of the frame's ground truth
and each one's seconds, then each model's worst.
"""
import argparse
import glob
import os
import sys
import time
import zlib
import struct

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools"))
import pure  # noqa: E402

pure.install()
import numpy as np  # noqa: E402
from blobtree_ink import model as M  # noqa: E402
from blobtree_ink.agents import Session, Settings  # noqa: E402
from blobtree_ink.agents.baseline import Baseline  # noqa: E402
from blobtree_ink.blackboard.view import View  # noqa: E402
from outlinemeasure import (THREE_QUARTER, Camera, coverage, dangling_ends, drawn, gaps, ground_truth,  # noqa: E402
                            precision, raster, towards, view_truth, views)

HERE = os.path.dirname(os.path.abspath(__file__))
EXAMPLES = os.path.join(HERE, "..", "examples")
RES = {"heart": 20, "train": 15, "shell": 25}      # the papers' grid resolutions


def grid_for(a, name):
    """The MASSRIS grid: --grid, else the papers' for the model, else the session's."""
    return a.grid or RES.get(name, Settings.resolution)


def massris(model, view, grid, agents, previous=None, remember=False):
    s = Session(model, view, Settings(resolution=grid, agents=agents), previous=previous, remember=remember)
    s.request("OUTLINES")
    return s


def curve(gt, make, step_fn, outlines_fn, limit):
    t0 = time.perf_counter()
    obj = make()
    spent = time.perf_counter() - t0
    pts = []
    while spent < limit:
        t = time.perf_counter()
        more = step_fn(obj)
        spent += time.perf_counter() - t
        cov = coverage(gt, raster(CAM[0], drawn(outlines_fn(obj))))
        pts.append((spent, cov))
        if cov >= 0.95 or more is False:
            break
    return pts


CAM = [None]


def t95(pts):
    for t, c in pts:
        if c >= 0.95:
            return t
    return None


def png(path, series, limit):
    W, H = 640, 360
    img = np.full((H, W, 3), 255, np.uint8)
    img[H - 20, 20:W - 10] = 0
    img[10:H - 19, 20] = 0
    img[H - 20 - int(0.95 * (H - 40)), 20:W - 10:4] = (160, 160, 160)
    colours = [(200, 30, 30), (30, 30, 200), (30, 150, 30), (200, 120, 0), (120, 0, 160), (0, 140, 140)]
    for (label, pts), col in zip(series, colours):
        xs = [20 + int((W - 40) * min(t, limit) / limit) for t, _ in pts]
        ys = [H - 20 - int((H - 40) * c) for _, c in pts]
        for (x0, y0), (x1, y1) in zip(zip(xs, ys), zip(xs[1:], ys[1:])):
            for s in np.linspace(0, 1, max(abs(x1 - x0), abs(y1 - y0), 1) + 1):
                img[int(round(y0 + s * (y1 - y0))), int(round(x0 + s * (x1 - x0)))] = col
    raw = b"".join(b"\x00" + img[y].tobytes() for y in range(H))

    def chunk(t, d):
        return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xffffffff)
    with open(path, "wb") as fh:
        fh.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", W, H, 8, 2, 0, 0, 0)) +
                 chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


def race(a, names):
    series = []
    print(f"{'model':7} {'GT px':>7} {'MASSRIS t95':>12} {'baseline t95':>13} {'ratio':>7}  final coverage")
    for name in names:
        model = M.load(os.path.join(EXAMPLES, f"{name}.json"))
        ev = M.Evaluator(model)
        cam = Camera(ev)
        CAM[0] = cam
        view = View(eye=cam.eye)
        gt = ground_truth(ev, view, cam, a.gt_res)
        mas = curve(gt, lambda: massris(model, view, grid_for(a, name), a.agents),
                    lambda s: (s.step(), not s.done)[1], lambda s: s.outlines(), a.limit)
        base = None if a.no_baseline else curve(
            gt, lambda: Baseline(model, view, particles=1000), lambda b: b.step(budget=2.0),
            lambda b: b.outlines(), a.limit)
        tm, tb = t95(mas), (t95(base) if base else None)
        ratio = f"{tb / tm:.1f}x" if tm and tb else "-"
        said = f"baseline {base[-1][1]:.3f} after {base[-1][0]:.1f}s" if base else "baseline not run"
        print(f"{name:7} {int(gt.sum()):7d} {tm if tm is None else round(tm, 3)!s:>12} "
              f"{tb if tb is None else round(tb, 2)!s:>13} {ratio:>7}  MASSRIS {mas[-1][1]:.3f} "
              f"after {mas[-1][0]:.1f}s, {said}", flush=True)
        series += [(f"{name} MASSRIS", mas), (f"{name} baseline", base)]
    if a.no_baseline:                   # the saved plot is the comparison; a MASSRIS-only run keeps it
        return
    png(os.path.join(HERE, "outlines.png"), series, a.limit)
    print("curves saved to bench/outlines.png (MASSRIS then baseline per model, in model order; "
          "x: seconds up to the limit, y: coverage, grey: 95 %)")


def to_end(make, limit):
    """A session made and run to its end or to limit seconds, its construction included:
    the session, its seconds and whether it ended by itself."""
    t0 = time.perf_counter()
    s = make()
    s.run(seconds=max(limit - (time.perf_counter() - t0), 0.0))
    return s, time.perf_counter() - t0, s.done


def one_view(a, name, model, ev, azimuth, elevation):
    """A row of the views table for one view of a model."""
    cam = Camera(ev, towards(azimuth, elevation))
    view = View(eye=cam.eye)
    gt, line, near = view_truth(ev, view, cam, a.gt_res)
    s, spent, done = to_end(lambda: massris(model, view, grid_for(a, name), a.agents), a.limit)
    outs = s.outlines()
    traced = raster(cam, drawn(outs))
    return (coverage(gt, traced), precision(near, traced), gaps(line, traced), dangling_ends(cam, outs),
            spent, done)


ROW = "{:14} {:>5} {:>5} {:>8} {:>9} {:>5} {:>8} {:>8} {:>6}"


def row(name, az, el, cov, prec, gap, ends, spent, ended):
    print(ROW.format(name, az, el, f"{cov:.3f}", f"{prec:.3f}", gap, ends, f"{spent:.2f}", ended), flush=True)


def around(a, names):
    print(ROW.format("model", "az", "el", "coverage", "precision", "gaps", "dangling", "seconds", "ended"))
    worst = []
    for name in names:
        model = M.load(os.path.join(EXAMPLES, f"{name}.json"))
        ev = M.Evaluator(model)
        rows = []
        for az, el in views(a.views):
            rows.append(one_view(a, name, model, ev, az, el))
            row(name, f"{az:.0f}", f"{el:.0f}", *rows[-1][:-1], "done" if rows[-1][-1] else "limit")
        cov, prec, gap, ends, spent, done = zip(*rows)
        worst.append((name, min(cov), min(prec), max(gap), max(ends), max(spent),
                      f"{done.count(False)} limit" if False in done else "done"))
    print(f"\nworst over the {a.views} views of each model")
    print(ROW.format("model", "", "", "coverage", "precision", "gaps", "dangling", "seconds", "ended"))
    for name, *w in worst:
        row(name, "", "", *w)


TURN_ROW = "{:14} {:>5} {:>8} {:>8} {:>9} {:>9} {:>8} {:>8}"


def turning(a, names):
    """Frames of a turning eye, going on from the last frame against from scratch."""
    print(TURN_ROW.format("model", "frame", "going in", "scratch", "coverage", "coverage", "seconds", "seconds"))
    print(TURN_ROW.format("", "", "scratch", "in going", "going", "scratch", "going", "scratch"))
    d = np.asarray(THREE_QUARTER, float)
    start, elevation = np.degrees(np.arctan2(d[1], d[0])), np.degrees(np.arctan2(d[2], np.hypot(d[0], d[1])))
    worst = []
    for name in names:
        model = M.load(os.path.join(EXAMPLES, f"{name}.json"))
        ev = M.Evaluator(model)
        grid, previous, rows = grid_for(a, name), None, []
        for k in range(a.turning):
            cam = Camera(ev, towards(start + k * a.turn, elevation))
            view = View(eye=cam.eye)
            going, t_going, _ = to_end(lambda: massris(ev, view, grid, a.agents, previous, True), a.limit)
            previous = going.continuation()
            if k == 0:
                continue
            scratch, t_scratch, _ = to_end(lambda: massris(model, view, grid, a.agents), a.limit)
            gt, _, _ = view_truth(ev, view, cam, a.gt_res)
            A, B = raster(cam, drawn(going.outlines())), raster(cam, drawn(scratch.outlines()))
            rows.append((precision(B, A), precision(A, B), coverage(gt, A), coverage(gt, B), t_going, t_scratch))
            print(TURN_ROW.format(name, k, *(f"{x:.3f}" for x in rows[-1][:4]), *(f"{x:.2f}" for x in rows[-1][4:])),
                  flush=True)
        c = list(zip(*rows))
        worst.append((name, min(c[0]), min(c[1]), min(c[2]), min(c[3]), max(c[4]), max(c[5])))
    print(f"\nworst over frames 1-{a.turning - 1} of each model (the eye turning {a.turn:g} degrees a frame)")
    for name, *w in worst:
        print(TURN_ROW.format(name, "", *(f"{x:.3f}" for x in w[:4]), *(f"{x:.2f}" for x in w[4:])))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--models", default="heart,train,shell", help="comma-separated examples, or all")
    ap.add_argument("--gt-res", type=int, default=256)
    ap.add_argument("--limit", type=float, default=60.0)
    ap.add_argument("--grid", type=int, default=None, help="MASSRIS grid (default: the papers' per model)")
    ap.add_argument("--agents", type=int, default=Settings.agents, help="MASSRIS agents (default: the session's)")
    ap.add_argument("--no-baseline", action="store_true", help="run MASSRIS only (the baseline takes the limit); no plot is saved")
    ap.add_argument("--views", type=int, default=None,
                    help="run MASSRIS to its end from N (8 or more) views all round each model instead")
    ap.add_argument("--turning", type=int, default=None,
                    help="run N (2 or more) frames of a turning eye, going on from the last and from scratch")
    ap.add_argument("--turn", type=float, default=2.0, help="degrees the eye turns a frame (--turning)")
    a = ap.parse_args()
    if a.views is not None and a.views < 8:
        ap.error("--views needs 8 or more views")
    if a.turning is not None and (a.turning < 2 or not np.isfinite(a.turn)):
        ap.error("--turning needs 2 or more frames and --turn a finite number of degrees")
    names = a.models.split(",") if a.models != "all" else sorted(
        os.path.splitext(os.path.basename(p))[0] for p in glob.glob(os.path.join(EXAMPLES, "*.json")))
    if a.turning is not None:
        turning(a, names)
    else:
        (race if a.views is None else around)(a, names)


if __name__ == "__main__":
    main()
