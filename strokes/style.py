"""A drawing style and the one function that turns a sampling session into plain
strokes with it. The command line, the Illustrate operator and the tests all go
through :func:`place`, so there is one path from agents to strokes.

A style says which layers to draw (outlines, hatching, stipples, strokes from the
feature chains, short strokes on polygon centres), the flow field and steering weights
of the smarticles (a preset name of :data:`smarticles.PRESETS` or a dict), flocks,
the light thresholds and how much the light sets each point's radius and opacity.
"""
from dataclasses import dataclass, fields, replace

import numpy as np

from . import layers as L
from . import smarticles as sm
from .data import LAYER_OF_KIND, Stroke, StrokeSet
from .visibility import split_visible_many

LAYER_SWITCHES = ("outlines", "hatching", "stipples", "chains", "short")
SURFACES = ("all", "convex", "concave")
WEIGHT_NAMES = ("flow", "wander", "separation", "alignment", "cohesion", "containment")


@dataclass
class Style:
    outlines: bool = True
    hatching: bool = False
    stipples: bool = False
    chains: bool = False                 # strokes started from the feature chains
    short: bool = False                  # short strokes centred on polygon centres
    hatch_field: str = "dir1"            # dir1, dir2, contour, axis, straight
    hatch_axis: tuple = (0.0, 0.0, 1.0)
    cross_hatching: bool = True          # a second layer along cross_field in the darkest shade
    cross_field: str = "dir2"
    surface: str = "all"                 # start hatching only on convex or concave regions
    weights: object = "hatching"         # preset name or {behaviour: weight}
    flock_size: int = 1                  # > 1: every start spawns a flock of this many
    shade_lower: float = 0.25
    shade_upper: float = 0.6
    hatch_steps: int = 10
    chain_step: int = 3                  # every n-th chain point starts a stroke
    chain_angle: float = 90.0            # degrees between the chain and its strokes
    chain_field: str = "straight"
    chain_distance: float = 3.0          # in blackboard cells from the feature line
    stipple_every: int = 3
    line_width: float = 1.0              # times the base line radius
    contrast: float = 1.0                # 0: uniform strokes; 1: radius and opacity follow the shade

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
        for name, lo, hi in (("shade_lower", 0.0, 1.0), ("shade_upper", 0.0, 1.0), ("chain_angle", -180.0, 180.0),
                             ("chain_distance", 0.01, 100.0), ("line_width", 0.01, 100.0), ("contrast", 0.0, 1.0)):
            v = getattr(self, name)
            if not isinstance(v, (int, float, np.floating)) or not np.isfinite(v) or not lo <= v <= hi:
                raise ValueError(f"{name} must be a number from {lo:g} to {hi:g}, got {v!r}")
        if self.shade_lower > self.shade_upper:
            raise ValueError(f"shade_lower ({self.shade_lower:g}) must not exceed shade_upper "
                             f"({self.shade_upper:g})")
        return self

    def resolved_weights(self):
        w = self.weights
        if isinstance(w, str):
            if w not in sm.PRESETS:
                raise ValueError(f"weights preset must be one of {', '.join(sm.PRESETS)}, got {w!r}")
            return dict(sm.PRESETS[w])
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
    "hatched": Style(hatching=True),                                       # principal directions, cross-hatched
    "flocked": Style(hatching=True, cross_hatching=False, weights="flock", flock_size=4,
                     shade_upper=0.65),                                     # Smarticles fig. 4 (sketching)
    "silhouette-shading": Style(chains=True, chain_step=2),                # Smarticles fig. 3 left
    "short-strokes": Style(short=True, stipples=True),                     # MASSRIS fig. 1 (jug)
    "technical": Style(hatching=True, hatch_field="axis", cross_hatching=False),   # Smarticles fig. 3 right
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


def default_light(centre, eye):
    """Light from the upper left of the viewer, as illustrators draw it (a unit
    direction towards the light)."""
    d = np.asarray(eye, float) - np.asarray(centre, float)
    d /= np.linalg.norm(d)
    right = np.cross([0.0, 0.0, 1.0], d)          # the viewer's right (d points at the eye)
    right /= max(np.linalg.norm(right), 1e-12)
    light = 0.5 * d - 0.6 * right + 0.7 * np.array([0.0, 0.0, 1.0])
    return light / np.linalg.norm(light)


def outline_strokes(outlines, ev, eye, radius, light=None, contrast=0.0):
    """Visible parts of outlines as plain strokes; with a light, the side turned from
    it is drawn heavier (by ``contrast``)."""
    out = StrokeSet()
    polys, norms = [], []
    for o in outlines:
        pts, nrm = o.points, o.normals
        if o.closed:
            pts, nrm = np.vstack([pts, pts[:1]]), np.vstack([nrm, nrm[:1]])
        polys.append(pts)
        norms.append(nrm)
    for o, pts, nrm, runs in zip(outlines, polys, norms, split_visible_many(ev, polys, eye, norms)):
        whole = o.closed and runs == [(0, len(pts))]
        for a, b in runs:
            end = b - 1 if whole else b
            seg = pts[a:end]
            if light is None:
                r = np.full(len(seg), float(radius))
            else:
                r, _ = L.tone(L.lighting(nrm[a:end], light), 1.0, radius, 0.5 * contrast)
            out.add(LAYER_OF_KIND[o.kind], Stroke(seg, r, np.ones(len(seg)), cyclic=whole))
    return out


def place(session, eye, light, st, rng, line_radius, region=None):
    """All the layers of style ``st`` for a sampling session (its outlines, polygon
    vertices and faces) as a StrokeSet; ``region`` restricts the stroke layers."""
    st.check()
    ev = session.ev
    r = line_radius * st.line_width
    outlines = session.outlines()
    strokes = outline_strokes(outlines, ev, eye, r, light, st.contrast) if st.outlines else StrokeSet()
    step = 0.3 * session.h
    w = st.resolved_weights()
    V, N = session.mesh.vertices, session.vertex_normals
    keep = np.ones(len(V), bool) if region is None else region.contains(V)
    if st.surface != "all":
        mean = session.vertex_curvature["mean"]
        keep &= mean > 0 if st.surface == "convex" else mean < 0
    V, N = V[keep], N[keep]
    kw = dict(radius=0.6 * r, region=region, contrast=st.contrast, weights=w)
    if st.hatching:
        rules = sm.StrokeRules(max_steps=st.hatch_steps, region=region,
                               stop_on_curvature_sign=st.surface != "all")
        for s in L.hatching(ev, V, N, eye, light, step, rng, field=st.hatch_field, axis=st.hatch_axis,
                            lower=st.shade_lower, upper=st.shade_upper, rules=rules,
                            flock_size=st.flock_size, **kw):
            strokes.add("Hatching", s)
        if st.cross_hatching:           # cross-hatching in the darkest part of the shade
            up = 0.5 * (st.shade_lower + st.shade_upper)
            for s in L.hatching(ev, V, N, eye, light, step, rng, field=st.cross_field, axis=st.hatch_axis,
                                lower=0.4 * st.shade_lower, upper=up, rules=rules, flock_size=st.flock_size,
                                **dict(kw, radius=0.5 * r)):
                strokes.add("Hatching", s)
    if st.chains and outlines:
        near = [o for o in outlines if region is None or region.contains(o.points).any()]
        for s in L.chain_strokes(ev, near, eye, light, step, rng, every=st.chain_step, angle=st.chain_angle,
                                 field=st.chain_field, axis=st.hatch_axis,
                                 max_distance=st.chain_distance * session.h, lower=st.shade_lower,
                                 upper=st.shade_upper, **kw):
            strokes.add("Hatching", s)
    if st.short:
        C, CN = face_centres(session)
        inside = np.ones(len(C), bool) if region is None else region.contains(C)
        for s in L.short_strokes(ev, C[inside], CN[inside], eye, light, step, rng, field=st.hatch_field,
                                 axis=st.hatch_axis, lower=st.shade_lower, upper=st.shade_upper + 0.05, **kw):
            strokes.add("Strokes", s)
    if st.stipples:
        for s in L.stipples(ev, V[::2], N[::2], eye, light, 0.5 * step, rng, every=st.stipple_every,
                            lower=0.8 * st.shade_lower, upper=0.92 * st.shade_upper, radius=1.2 * r,
                            region=region, contrast=st.contrast):
            strokes.add("Stipples", s)
    return strokes


def face_centres(session):
    """Centres and normals of the rough polygonisation's faces."""
    q = session.mesh.quads
    C = session.mesh.vertices[q].mean(axis=1)
    N = session.vertex_normals[q].sum(axis=1)
    return C, N / np.maximum(np.linalg.norm(N, axis=1, keepdims=True), 1e-300)
