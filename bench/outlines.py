"""Feature-outline coverage over time: MASSRIS against the WH particle baseline.

    python bench/outlines.py [--models heart,train,shell] [--gt-res 256] [--limit 60]
                             [--grid N] [--agents N]

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
"""
import argparse
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
from blobtree_ink.model.vectors import cross  # noqa: E402
from blobtree_ink.agents import Session, Settings  # noqa: E402
from blobtree_ink.agents.baseline import Baseline  # noqa: E402
from blobtree_ink.agents.surface import Surface  # noqa: E402
from blobtree_ink.agents.tracer import refine_seeds  # noqa: E402
from blobtree_ink.blackboard.board import KIND_ID  # noqa: E402
from blobtree_ink.blackboard.edges import DEFAULT_CREASE_ANGLE, process_edges  # noqa: E402
from blobtree_ink.blackboard.polygonise import polygonise, surface_box  # noqa: E402
from blobtree_ink.blackboard.view import View  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
PX = 1024
RES = {"heart": 20, "train": 15, "shell": 25}      # the papers' grid resolutions


class Camera:
    def __init__(self, ev):
        lo, hi = surface_box(ev)
        self.c = 0.5 * (lo + hi)
        r = 0.5 * np.linalg.norm(hi - lo)
        d = np.array([1.0, -1.4, 0.8])
        d /= np.linalg.norm(d)
        self.eye = self.c + 3.0 * r * d
        self.f = -d
        self.right = cross(self.f, [0, 0, 1.0])
        self.right /= np.linalg.norm(self.right)
        self.up = cross(self.right, self.f)
        self.half = r / (3.0 * r) * 1.05             # tan of the half field of view

    def pixels(self, P):
        v = P - self.eye
        z = v @ self.f
        x = (v @ self.right) / z / self.half
        y = (v @ self.up) / z / self.half
        return np.stack([(x + 1) * PX / 2, (1 - y) * PX / 2], axis=1)


def raster(cam, polylines):
    """Pixels the polylines pass through (segments sampled every quarter pixel, vectorised)."""
    img = np.zeros((PX, PX), bool)
    segs = []
    for P in polylines:
        q = cam.pixels(np.vstack([P, P]) if len(P) == 1 else P)
        segs.append(np.stack([q[:-1], q[1:]], axis=1))
    if not segs:
        return img
    S = np.concatenate(segs)                                    # (m, 2, 2)
    L = np.linalg.norm(S[:, 1] - S[:, 0], axis=1)
    k = np.maximum(2, (4 * L).astype(int) + 2)
    seg = np.repeat(np.arange(len(S)), k)
    t = (np.arange(k.sum()) - np.repeat(np.cumsum(k) - k, k)) / np.repeat(k - 1, k)
    pts = S[seg, 0] + t[:, None] * (S[seg, 1] - S[seg, 0])
    ij = np.round(pts).astype(int)
    ok = (ij[:, 0] >= 0) & (ij[:, 0] < PX) & (ij[:, 1] >= 0) & (ij[:, 1] < PX)
    img[ij[ok, 1], ij[ok, 0]] = True
    return img


def dilate(img):
    out = img.copy()
    for dx in (-1, 0, 1):
        for dy in (-1, 0, 1):
            out |= np.roll(np.roll(img, dx, 0), dy, 1)
    return out


def ground_truth(ev, view, cam, res):
    mesh = polygonise(ev, res)
    f, g = ev.field_grad(mesh.vertices)
    n = -g / np.maximum(np.linalg.norm(g, axis=1, keepdims=True), 1e-300)
    feats = process_edges(mesh, n, np.ones(len(n)), view)
    _, a, b = feats["crease"]
    surf = Surface(ev, view)
    crease = np.full(len(a), KIND_ID["crease"], np.int64)
    X, _, _, _, _, _, real, _, _ = refine_seeds(surf, crease, a, b, 1e-8 * ev.scale, DEFAULT_CREASE_ANGLE)
    print(f"  ground truth: {len(feats['silhouette'][0])} silhouette points, {int(real.sum())} of "
          f"{len(a)} crease candidates are creases", flush=True)
    pts = np.concatenate([feats["silhouette"][0], X[real]])
    img = np.zeros((PX, PX), bool)
    ij = np.round(cam.pixels(pts)).astype(int)
    ok = (ij[:, 0] >= 0) & (ij[:, 0] < PX) & (ij[:, 1] >= 0) & (ij[:, 1] < PX)
    img[ij[ok, 1], ij[ok, 0]] = True
    return img


def curve(gt, make, step_fn, outlines_fn, limit):
    t0 = time.perf_counter()
    obj = make()
    spent = time.perf_counter() - t0
    pts = []
    while spent < limit:
        t = time.perf_counter()
        more = step_fn(obj)
        spent += time.perf_counter() - t
        cov = (dilate(raster(CAM[0], [o.points for o in outlines_fn(obj)])) & gt).sum() / max(gt.sum(), 1)
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


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--models", default="heart,train,shell")
    ap.add_argument("--gt-res", type=int, default=256)
    ap.add_argument("--limit", type=float, default=60.0)
    ap.add_argument("--grid", type=int, default=None, help="MASSRIS grid (default: the papers' per model)")
    ap.add_argument("--agents", type=int, default=Settings.agents, help="MASSRIS agents (default: the session's)")
    ap.add_argument("--no-baseline", action="store_true", help="run MASSRIS only (the baseline takes the limit); no plot is saved")
    a = ap.parse_args()
    series = []
    print(f"{'model':7} {'GT px':>7} {'MASSRIS t95':>12} {'baseline t95':>13} {'ratio':>7}  final coverage")
    for name in a.models.split(","):
        model = M.load(os.path.join(HERE, "..", "examples", f"{name}.json"))
        ev = M.Evaluator(model)
        cam = Camera(ev)
        CAM[0] = cam
        view = View(eye=cam.eye)
        gt = ground_truth(ev, view, cam, a.gt_res)

        def make_massris():
            s = Session(model, view, Settings(resolution=a.grid or RES.get(name, 20), agents=a.agents))
            s.request("OUTLINES")
            return s
        mas = curve(gt, make_massris, lambda s: (s.step(), not s.done)[1], lambda s: s.outlines(), a.limit)
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


if __name__ == "__main__":
    main()
