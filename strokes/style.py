"""A drawing style, its presets, and the visible outlines as plain strokes. The stroke
layers a style draws are placed by the illustration pipeline (pipeline.layers), the one
path from agents to strokes.

A style says which layers to draw (outlines, hatching, stipples, strokes from the
feature chains, short strokes on polygon centres), the flow field and steering weights
of the smarticles (a preset name of :data:`smarticles.PRESETS` or a dict), flocks,
the light thresholds and how much the light sets each point's radius and opacity.
"""
from dataclasses import dataclass, fields, replace

import numpy as np

from ..model.vectors import cross
from . import layers as L
from . import smarticles as sm
from .data import LAYER_OF_KIND, Stroke, StrokeSet
from .doubled import undoubled
from . import tone as TN
from .tone import lambert
from .visibility import piece, run_points, split_visible_many

FLOATS = ("shade_lower", "shade_upper", "chain_angle", "chain_distance", "line_width", "contrast")
LAYER_SWITCHES = ("outlines", "hatching", "stipples", "chains", "short")
STROKE_SWITCHES = ("hatching", "chains", "short", "stipples")        # the stroke layers, in drawing order
SURFACES = ("all", "convex", "concave")
WEIGHT_NAMES = ("flow", "wander", "separation", "alignment", "cohesion", "containment")
SPECK = 4.0           # trace steps: a visible piece of a suggestive contour or apparent ridge shorter than this
SPECKLED = ("suggestive", "ridges")   # is not drawn (the kinds, found where a curvature peaks or vanishes)
DOT = 4.0             # line widths: a whole outline (any kind) that fits in a box this wide draws as a dot
DRAWN_TWICE = ("Silhouette", "Crease")   # the layers whose strokes running side by side are one line (strokes.doubled)


@dataclass
class Style:
    outlines: bool = True
    hatching: bool = False
    stipples: bool = False
    chains: bool = False                 # strokes started from the feature chains
    short: bool = False                  # short strokes centred on polygon centres
    hatch_field: str = "dir1"            # dir1, dir2, diagonal, contour, axis, level, straight
    hatch_axis: tuple = (0.0, 0.0, 1.0)
    cross_hatching: bool = True          # a second layer along cross_field in the darkest shade
    cross_field: str = "diagonal"
    surface: str = "all"                 # start hatching only on convex or concave regions
    weights: object = "hatching"         # preset name or {behaviour: weight}
    flock_size: int = 1                  # > 1: every start spawns a flock of this many
    shade_lower: float = 0.1            # the light below which the ink is darkest (strokes.tone)
    shade_upper: float = 0.7            # the highlight threshold: above it the paper stays white
    hatch_steps: int = 20                # a hatching line's steps each way from its seed, at most
    chain_step: int = 3                  # every n-th chain point starts a stroke
    chain_angle: float = 90.0            # degrees between the chain and its strokes
    chain_field: str = "straight"
    chain_distance: float = 12.0         # from the feature line, in stroke units, at most (the tone ends them sooner)
    stipple_every: int = 2
    line_width: float = 1.0              # times the base line radius
    contrast: float = 1.0                # how much of the tonal range the light spans (strokes.tone)

    def check(self):
        """Raise ValueError naming the first bad setting."""
        for name in ("hatch_field", "cross_field", "chain_field"):
            if getattr(self, name) not in L.FIELDS:
                raise ValueError(f"{name} must be one of {', '.join(L.FIELDS)}, got {getattr(self, name)!r}")
        if self.surface not in SURFACES:
            raise ValueError(f"surface must be one of {', '.join(SURFACES)}, got {self.surface!r}")
        ax = np.asarray(self.hatch_axis, float)
        if ax.shape != (3,) or not np.all(np.isfinite(ax)) or not np.linalg.norm(ax) > 0:
            raise ValueError(f"hatch_axis must be three finite numbers, not all zero, got {self.hatch_axis!r}")
        self.resolved_weights()
        for name, lo, hi in (("flock_size", 1, 64), ("hatch_steps", 1, 1000), ("chain_step", 1, 10000),
                             ("stipple_every", 1, 1000)):
            v = getattr(self, name)
            if not isinstance(v, (int, np.integer)) or isinstance(v, bool) or not lo <= v <= hi:
                raise ValueError(f"{name} must be a whole number from {lo} to {hi}, got {v!r}")
        TN.check(self.shade_lower, self.shade_upper, self.contrast)
        for name, lo, hi in (("chain_angle", -180.0, 180.0), ("chain_distance", 0.01, 100.0),
                             ("line_width", 0.01, 100.0)):
            v = getattr(self, name)
            if not isinstance(v, (int, float, np.floating)) or not np.isfinite(v) or not lo <= v <= hi:
                raise ValueError(f"{name} must be a number from {lo:g} to {hi:g}, got {v!r}")
        return self

    def rounded(self):
        """This style with its numbers as Blender keeps them (single precision), so that a
        style read from a tree and one given on the command line draw alike to the bit
        (marks spaced by their neighbours hang on every threshold)."""
        def f32(x):
            return float(np.float32(x))
        w = self.weights if isinstance(self.weights, str) else {k: f32(v) for k, v in self.weights.items()}
        return replace(self, hatch_axis=tuple(f32(x) for x in self.hatch_axis), weights=w,
                       **{k: f32(getattr(self, k)) for k in FLOATS})

    def stroke_switches(self):
        """The stroke layers this style draws, by switch name, in drawing order."""
        return tuple(k for k in STROKE_SWITCHES if getattr(self, k))

    def resolved_weights(self):
        w = self.weights
        if isinstance(w, str):
            if w not in sm.PRESETS:
                raise ValueError(f"weights preset must be one of {', '.join(sm.PRESETS)}, got {w!r}")
            return {k: float(np.float32(v)) for k, v in sm.PRESETS[w].items()}
        if not isinstance(w, dict) or not w:
            raise ValueError(f"weights must be a preset name or a dict of behaviour weights, got {w!r}")
        for k, v in w.items():
            if k not in WEIGHT_NAMES:
                raise ValueError(f"unknown behaviour {k!r} in weights; one of {', '.join(WEIGHT_NAMES)}")
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not np.isfinite(v) or not 0 <= v <= 100:
                raise ValueError(f"weight {k} must be a number from 0 to 100, got {v!r}")
        return {k: float(v) for k, v in w.items()}


# The looks of the papers' figures.
STYLES = {
    "outlines": Style(),
    "stippled": Style(stipples=True),                                      # MASSRIS fig. 1, 6
    "hatched": Style(hatching=True),                                       # dir1, cross-hatched diagonally
    "flocked": Style(hatching=True, cross_hatching=False, weights="flock", flock_size=4),   # Smarticles fig. 4
    "silhouette-shading": Style(chains=True, chain_step=2),                # Smarticles fig. 3 left
    "short-strokes": Style(short=True, stipples=True),                     # MASSRIS fig. 1 (jug)
    "technical": Style(hatching=True, hatch_field="level", cross_hatching=False),  # horizontal (Smarticles fig. 3 right)
    "contour": Style(hatching=True, hatch_field="contour", cross_hatching=False),
}


def style(name, **changes):
    """A named style with some settings changed, checked."""
    if name not in STYLES:
        raise ValueError(f"unknown style {name!r}; one of {', '.join(STYLES)}")
    bad = [k for k in changes if k not in {f.name for f in fields(Style)}]
    if bad:
        raise ValueError(f"unknown style setting {bad[0]!r}")
    return replace(STYLES[name], **changes).check()


UP = np.array([0.0, 0.0, 1.0])          # the world's up (Blender's z)
ALONG = np.array([1.0, 0.35])           # open outlines run this way across the view (right, a little up)


def view_right(eye, at):
    """The view's right (unit) at the point ``at`` seen from ``eye``: across the line of
    sight and the world's up (the y axis's when looking nearly straight up or down)."""
    forward = np.asarray(at, float) - np.asarray(eye, float)
    forward /= max(np.linalg.norm(forward), 1e-300)
    up = UP if abs(forward @ UP) < 0.99 else np.array([0.0, 1.0, 0.0])
    right = cross(forward, up)
    return right / np.linalg.norm(right)


def canonical(points, closed, eye):
    """The order an outline's points are drawn in, the same from frame to frame as the
    outline moves: a closed one anticlockwise as seen from the eye, from its topmost
    point; an open one from the end that puts the other along ALONG in the view.
    Returns the index order (Grease Pencil modifiers along strokes then do not crawl)."""
    n = len(points)
    order = np.arange(n)
    if n < 2:
        return order
    forward = np.mean(points, axis=0) - np.asarray(eye, float)
    forward /= max(np.linalg.norm(forward), 1e-300)
    right = view_right(eye, np.mean(points, axis=0))
    xy = np.stack([points @ right, points @ cross(right, forward)], axis=1)
    if not closed:
        return order[::-1] if (xy[-1] - xy[0]) @ ALONG < 0 else order
    x, y = xy[:, 0], xy[:, 1]
    if (x * np.roll(y, -1) - np.roll(x, -1) * y).sum() < 0:        # clockwise: turn it round
        order = order[::-1]
    return np.roll(order, -int(np.argmax(y[order])))


def heavier(normals, light, radius, contrast):
    """An outline's radius along it: heavier on the side turned from the light, from 0.75
    to 1.25 times ``radius`` at contrast 1 (uniform at 0)."""
    lit = lambert(normals, light)
    return radius * (1.0 + 0.5 * float(contrast) * (0.5 - lit))


def is_dot(points, radius):
    """Whether a polyline fits in a box whose diagonal is under DOT widths of a line of
    that ``radius`` (then it draws as a dot, not a line)."""
    P = np.asarray(points, float).reshape(-1, 3)
    return len(P) == 0 or float(np.linalg.norm(P.max(axis=0) - P.min(axis=0))) < DOT * 2.0 * radius


def outline_strokes(outlines, ev, eye, radius, light=None, contrast=0.0, sight=None):
    """Visible parts of outlines as plain strokes (hidden by ``sight``, a
    strokes.visibility.Sight: default the model's own solid alone), each in its
    :func:`canonical` order;
    with a light, the side turned from it is drawn heavier (by ``contrast``). A visible
    piece of a suggestive contour or an apparent ridge shorter than SPECK of its trace
    steps is not drawn: a speck on the paper, not a line (a silhouette's is: the end of
    a real contour). Nor is a whole outline whose box's diagonal is under DOT line
    widths (a tiny contour loop round a bump, or a scrap of one): drawn, it is a dot.
    Silhouettes and creases that run side by side on the paper, a line width or so
    apart, are one line drawn twice: the shorter leaves its stretch along the longer
    out (strokes.doubled)."""
    out = StrokeSet()
    polys, norms = [], []
    outlines = [o for o in outlines if not is_dot(o.points, radius)]
    for o in outlines:
        order = canonical(o.points, o.closed, eye)
        pts, nrm = o.points[order], o.normals[order]
        if o.closed:
            pts, nrm = np.vstack([pts, pts[:1]]), np.vstack([nrm, nrm[:1]])
        polys.append(pts)
        norms.append(nrm)
    sight = ev if sight is None else sight
    for o, pts, nrm, runs in zip(outlines, polys, norms, split_visible_many(sight, polys, eye, norms)):
        whole = o.closed and len(runs) == 1 and runs[0][:2] == (0, len(pts))
        if whole:
            runs = [runs[0]._replace(b=runs[0].b - 1)]
        pieces = [(run_points(pts, run), piece(nrm, run)) for run in runs]
        if o.closed and len(runs) > 1 and runs[0].a == 0 and runs[-1].b == len(pts):
            # a run across a loop's start is one stroke (its last point is the loop's first)
            (p0, n0), (p1, n1) = pieces[0], pieces.pop()
            pieces[0] = (np.concatenate([p1[:-1], p0]), np.concatenate([n1[:-1], n0]))
        for seg, seg_n in pieces:
            if o.kind in SPECKLED and np.linalg.norm(np.diff(seg, axis=0), axis=1).sum() < SPECK * o.step:
                continue
            r = np.full(len(seg), float(radius)) if light is None else heavier(seg_n, light, radius, contrast)
            out.add(LAYER_OF_KIND[o.kind], Stroke(seg, r, np.ones(len(seg)), cyclic=whole))
    drawn = [(name, s) for name in DRAWN_TWICE for s in out.layers[name]]
    for name in DRAWN_TWICE:
        out.layers[name] = []
    for (name, _), left in zip(drawn, undoubled([s for _, s in drawn], eye)):
        out.layers[name] += left
    return out
