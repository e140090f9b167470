"""The stroke layers of a style, each from a sampling session's plain result
(agents.Sampling): the visible outlines, hatching and cross-hatching, strokes from the
feature chains, short strokes on the polygon centres, stipples, and a single stroke.
One function per layer; the illustration calls them in a fixed order on one random
generator, a layer in parts of its starts (strokes.layers places them,
strokes.smarticles moves them)."""
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
CHUNK = 1000                # starts per part of a stroke layer (one pipeline step each)
CHUNK_OUTLINES = 40         # outlines per part of the chain strokes


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


def _chunks(n, size):
    """Slices of ``size`` covering range(n) (at least one, maybe empty)."""
    return [slice(a, a + size) for a in range(0, n, size)] or [slice(0, 0)]


def _common(st, line_radius, region):
    return dict(radius=0.6 * radius(st, line_radius), region=region, contrast=st.contrast,
                weights=st.resolved_weights())


# Each stroke layer is drawn in parts (chunks of its starts), one part per pipeline
# step, so that a stopped illustration keeps a partly drawn layer: ``parts`` lists
# them from the sampling, ``draw`` draws one.

def hatching_parts(sampling, st, region):
    V, N = starts(sampling, st, region)
    return [(V[c], N[c]) for c in _chunks(len(V), CHUNK)]


def hatching(ev, sampling, eye, light, st, rng, line_radius, region, part, cross=False):
    """Hatching along the style's flow field (or, with ``cross``, the cross-hatching
    along its cross field in the darkest part of the shade) from a part's starts."""
    V, N = part
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


def chains_parts(sampling, st, region):
    near = [o for o in sampling.outlines if region is None or region.contains(o.points).any()]
    features = np.concatenate([o.points for o in near]) if near else np.zeros((0, 3))
    return [(near[c], features) for c in _chunks(len(near), CHUNK_OUTLINES)]


def chains(ev, sampling, eye, light, st, rng, line_radius, region, part):
    """Strokes started from a part's feature chains (ending at a distance from all the
    chains near the region)."""
    outlines, features = part
    if not outlines:
        return []
    return L.chain_strokes(ev, outlines, eye, light, STEP * sampling.cell, rng, features=features,
                           every=st.chain_step,
                           angle=st.chain_angle, field=st.chain_field, axis=st.hatch_axis,
                           max_distance=st.chain_distance * sampling.cell, lower=st.shade_lower,
                           upper=st.shade_upper, **_common(st, line_radius, region))


def short_parts(sampling, st, region):
    C, CN = sampling.face_centres()
    inside = np.ones(len(C), bool) if region is None else region.contains(C)
    C, CN = C[inside], CN[inside]
    return [(C[c], CN[c]) for c in _chunks(len(C), CHUNK)]


def short(ev, sampling, eye, light, st, rng, line_radius, region, part):
    """Short strokes through a part's polygon centres."""
    C, CN = part
    return L.short_strokes(ev, C, CN, eye, light, STEP * sampling.cell, rng, field=st.hatch_field,
                           axis=st.hatch_axis, lower=st.shade_lower, upper=st.shade_upper + 0.05,
                           **_common(st, line_radius, region))


def stipples_parts(sampling, st, region):
    V, N = starts(sampling, st, region)
    V, N = V[::2], N[::2]                   # every other start
    return [(V[c], N[c]) for c in _chunks(len(V), CHUNK)]


def stipples(ev, sampling, eye, light, st, rng, line_radius, region, part):
    """Stipples from a part's wandering smarticles."""
    V, N = part
    return L.stipples(ev, V, N, eye, light, 0.5 * STEP * sampling.cell, rng, every=st.stipple_every,
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
