"""The stroke layers of a style, each from a sampling session's plain result
(agents.Sampling): the visible outlines, hatching and cross-hatching, strokes from the
feature chains, short strokes on the polygon centres, stipples, and a single stroke.
One function per layer; the illustration calls them in a fixed order on one random
generator (strokes.layers places them, strokes.smarticles moves them)."""
import numpy as np
from numpy.random import default_rng    # numpy imports it lazily: here, not in a run's first call

from ..model.projection import project
from ..model.tolerances import NEAR_SURFACE, on_surface
from ..strokes import layers as L
from ..strokes import smarticles as sm
from ..strokes.data import Stroke
from ..strokes.style import outline_strokes

STEP = 0.3                  # a smarticle's step, in blackboard cells (stipples take half)
SINGLE_STEPS = 60           # a single stroke's steps, at most


def radius(st, line_radius):
    """The radius of the style's lines."""
    return line_radius * st.line_width


def outlines(ev, sampling, eye, light, st, line_radius):
    """The visible parts of the outlines found (a StrokeSet of the outline layers)."""
    return outline_strokes(sampling.outlines, ev, eye, radius(st, line_radius), light, st.contrast)


def starts(sampling, st, region):
    """Where hatching and stipples start: the rough polygonisation's vertices (in the
    region, and on the style's surface: all, convex or concave) and their normals."""
    V, N = sampling.vertices, sampling.vertex_normals
    keep = np.ones(len(V), bool) if region is None else region.contains(V)
    if st.surface != "all":
        mean = sampling.vertex_curvature["mean"]
        keep &= mean > 0 if st.surface == "convex" else mean < 0
    return V[keep], N[keep]


def _common(st, line_radius, region):
    return dict(radius=0.6 * radius(st, line_radius), region=region, contrast=st.contrast,
                weights=st.resolved_weights())


def hatching(ev, sampling, eye, light, st, rng, line_radius, region=None, cross=False):
    """Hatching along the style's flow field (or, with ``cross``, the cross-hatching
    along its cross field in the darkest part of the shade)."""
    V, N = starts(sampling, st, region)
    kw = _common(st, line_radius, region)
    rules = sm.StrokeRules(max_steps=st.hatch_steps, region=region, stop_on_curvature_sign=st.surface != "all")
    step = STEP * sampling.cell
    if not cross:
        return L.hatching(ev, V, N, eye, light, step, rng, field=st.hatch_field, axis=st.hatch_axis,
                          lower=st.shade_lower, upper=st.shade_upper, rules=rules, flock_size=st.flock_size, **kw)
    up = 0.5 * (st.shade_lower + st.shade_upper)
    return L.hatching(ev, V, N, eye, light, step, rng, field=st.cross_field, axis=st.hatch_axis,
                      lower=0.4 * st.shade_lower, upper=up, rules=rules, flock_size=st.flock_size,
                      **dict(kw, radius=0.5 * radius(st, line_radius)))


def chains(ev, sampling, eye, light, st, rng, line_radius, region=None):
    """Strokes started from the feature chains (the outlines near the region)."""
    near = [o for o in sampling.outlines if region is None or region.contains(o.points).any()]
    if not near:
        return []
    return L.chain_strokes(ev, near, eye, light, STEP * sampling.cell, rng, every=st.chain_step,
                           angle=st.chain_angle, field=st.chain_field, axis=st.hatch_axis,
                           max_distance=st.chain_distance * sampling.cell, lower=st.shade_lower,
                           upper=st.shade_upper, **_common(st, line_radius, region))


def short(ev, sampling, eye, light, st, rng, line_radius, region=None):
    """Short strokes through the polygon centres."""
    C, CN = sampling.face_centres()
    inside = np.ones(len(C), bool) if region is None else region.contains(C)
    return L.short_strokes(ev, C[inside], CN[inside], eye, light, STEP * sampling.cell, rng, field=st.hatch_field,
                           axis=st.hatch_axis, lower=st.shade_lower, upper=st.shade_upper + 0.05,
                           **_common(st, line_radius, region))


def stipples(ev, sampling, eye, light, st, rng, line_radius, region=None):
    """Stipples from wandering smarticles (every other start)."""
    V, N = starts(sampling, st, region)
    return L.stipples(ev, V[::2], N[::2], eye, light, 0.5 * STEP * sampling.cell, rng, every=st.stipple_every,
                      lower=0.8 * st.shade_lower, upper=0.92 * st.shade_upper, radius=1.2 * radius(st, line_radius),
                      region=region, contrast=st.contrast)


def single_stroke(ev, sampling, eye, st, line_radius, point, seed=0):
    """One smarticle stroke from the surface point nearest ``point``, or None when the
    point is too far from the surface to project onto it (or the stroke would be a
    single point)."""
    P, f, _ = project(ev, np.asarray(point, float).reshape(1, 3), steps=8, max_step=0.05 * ev.scale)
    if not on_surface(f, ev.iso, NEAR_SURFACE)[0]:
        return None
    field = L.direction_field(st.hatch_field, st.hatch_axis, eye)
    res = sm.run(ev, P, field, STEP * sampling.cell, st.resolved_weights(),
                 sm.StrokeRules(max_steps=SINGLE_STEPS, stop_on_curvature_sign=False), default_rng(seed))
    p = res.paths[0]
    if len(p) < 2:
        return None
    r = radius(st, line_radius)
    return Stroke(p, np.full(len(p), r), np.ones(len(p)))
