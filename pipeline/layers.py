"""The stroke layers of a style, from a sampling session's plain result (agents.Sampling)
and the model's marks (model.marks): the visible outlines, hatching and cross-hatching,
strokes from the feature chains, short strokes, stipples, and a single stroke. One
function per layer; the illustration calls them in a fixed order, a layer in parts of
its starts (strokes.layers places them, strokes.smarticles moves them).

Every length of the strokes (a smarticle's step, the marks' spacing, how far chain
strokes go) is a multiple of the canvas's ``unit`` (framing.stroke_unit), which moving
the model or its parts does not change."""
from dataclasses import dataclass

import numpy as np

from ..model import Evaluator, keyed
from ..model.curvature import curvature
from ..model.marks import surface_marks
from ..model.projection import project
from ..model.tolerances import NEAR_SURFACE, on_surface
from ..strokes import crowding as CR
from ..strokes import layers as L
from ..strokes import smarticles as sm
from ..strokes import stipples as SP
from ..strokes.data import LAYER_OF_KIND, Stroke
from ..strokes.style import outline_strokes, view_right
from ..strokes.visibility import Sight

OUTLINE_LAYERS = tuple(LAYER_OF_KIND.values())
STEP = 0.3                  # a smarticle's step, in stroke units (stipples take half)
STIPPLE_RADIUS = 1.8        # a stipple's radius, in line radii (before its shade's tone)
SINGLE_STEPS = 60           # a single stroke's steps, at most
CHUNK = 1000                # starts per part of a stroke layer (one pipeline step each)
CHUNK_OUTLINES = 40         # outlines per part of the chain strokes
# Hatching, short strokes and stipples start at marks on the model (model.marks); each
# layer its own set (a salt), at a spacing in stroke units.
MARKS = {"hatching": (0, 0.78),
         "short": (1, 0.78),
         "stipples": (2, 0.8)}        # a wandering smarticle draws several dots


@dataclass(frozen=True)
class Canvas:
    """What every layer is drawn with: the model's evaluator, the eye, the light (a unit
    direction), the radius of a line of width 1 and the strokes' unit of length;
    ``settled``: the model is the last frame's, so likely the next frame's too (the
    smarticles' paths of every mark, kept with it, are made at once: in the next frames
    the light and the eye only choose among them); ``sight``: what hides the lines
    (strokes.visibility.Sight: the model and the other solids of its scene; None: the
    model alone)."""
    ev: object
    eye: np.ndarray
    light: np.ndarray
    line_radius: float
    unit: float
    settled: bool = False
    sight: object = None

    def radius(self, st):
        """The radius of the style's lines."""
        return self.line_radius * st.line_width


def sight(ev, occluders, known=()):
    """What hides the model's lines (strokes.visibility.Sight): the model and a job's
    occluders, each compiled here unless it is the model of one of the evaluators
    ``known`` (the last frame's: its plan and surface box are made); None without
    occluders (the model alone)."""
    if not occluders:
        return None
    return Sight(ev, tuple((_compiled(m, known), M) for m, M in occluders))


def occluder_evaluators(sight):
    """The evaluators of the other models of a :func:`sight` (none without one)."""
    return () if sight is None else tuple(ev for ev, _ in sight.others)


def _compiled(model, known):
    if isinstance(model, Evaluator):
        return model
    for ev in known:            # (the names first: two different models seldom share one, and compare at once)
        if ev.model is model or (ev.model.name == model.name and ev.model == model):
            return ev
    return Evaluator(model)


def outlines(cv, sampling, st):
    """The visible parts of the outlines found (a StrokeSet of the outline layers)."""
    return outline_strokes(sampling.outlines, cv.ev, cv.eye, cv.radius(st), cv.light, st.contrast, cv.sight)


def marks_of(cv, layer, owners, seed):
    """The marks a stroke layer starts from (hatching's serve cross-hatching too): the
    same in every frame for one seed."""
    salt, spacing = MARKS[layer]
    return surface_marks(cv.ev, spacing * cv.unit, int(keyed.combine(seed, salt)), owners)


def starts(ev, marks, st, region):
    """The marks in the region and on the style's surface (all, convex or concave)."""
    keep = np.ones(len(marks), bool) if region is None else region.contains(marks.points)
    if st.surface != "all" and keep.any():
        mean = curvature(ev, marks.points[keep])["mean"]
        keep[keep] = mean > 0 if st.surface == "convex" else mean < 0
    return marks.take(keep)


def _chunks(n, size):
    """Slices of ``size`` covering range(n) (at least one, maybe empty)."""
    return [slice(a, a + size) for a in range(0, n, size)] or [slice(0, 0)]


def _kept(cv, region, field, *rules):
    """The smarticles' paths kept with the model for one layer's rules (strokes.smarticles.
    run_kept): a path depends on the model, its mark and the rules alone, so a frame whose
    model is the last frame's takes them as they are (the light and the eye then decide
    which are drawn, where they are cut and what is hidden). None where a path depends on
    more: a request's region, or a flow field that looks at the eye."""
    if region is not None or field == "contour":
        return None
    return cv.ev.memo.setdefault(("paths",) + rules, {})


def _common(cv, st, region):
    return dict(radius=0.6 * cv.radius(st), region=region, contrast=st.contrast, weights=st.resolved_weights(),
                sight=cv.sight)


# Each stroke layer is drawn in parts (chunks of its starts), one part per pipeline
# step, so that a stopped illustration keeps a partly drawn layer: ``parts`` lists
# them, ``draw`` draws one.

def mark_parts(cv, sampling, marks, st, region):
    m = starts(cv.ev, marks, st, region)
    return [m.take(c) for c in _chunks(len(m), CHUNK)]


def crowding(cv, centre):
    """What keeps a hatching layer's strokes from crowding together on the paper (measured
    at the model's ``centre``), over its parts (strokes.crowding)."""
    return CR.Crowding(cv.eye, centre, CR.CROWD_GAP * cv.unit)


def hatching(cv, sampling, st, region, part, cross=False, crowding=None):
    """Hatching along the style's flow field (or, with ``cross``, the cross-hatching
    along its cross field in the darkest part of the shade) from a part's marks, each
    stroke thinned where it runs into a knot of the layer's strokes so far (``crowding``)."""
    kw = _common(cv, st, region)
    kw["crowding"] = crowding
    rules = sm.StrokeRules(max_steps=st.hatch_steps, region=region, stop_on_curvature_sign=st.surface != "all")
    step = STEP * cv.unit
    field = st.cross_field if cross else st.hatch_field
    paths = _kept(cv, region, field, "hatching", cross, field, tuple(st.hatch_axis), st.hatch_steps,
                  tuple(sorted(kw["weights"].items())), st.flock_size, st.surface != "all", step)
    if not cross:
        return L.hatching(cv.ev, part, cv.eye, cv.light, step, field=field, axis=st.hatch_axis,
                          lower=st.shade_lower, upper=st.shade_upper, rules=rules, flock_size=st.flock_size,
                          paths=paths, every_path=cv.settled, **kw)
    up = 0.5 * (st.shade_lower + st.shade_upper)
    return L.hatching(cv.ev, part, cv.eye, cv.light, step, field=field, axis=st.hatch_axis,
                      lower=0.4 * st.shade_lower, upper=up, rules=rules, flock_size=st.flock_size, salt=1,
                      paths=paths, every_path=cv.settled, **dict(kw, radius=0.5 * cv.radius(st)))


def chains_parts(cv, sampling, marks, st, region):
    near = [o for o in sampling.outlines if region is None or region.contains(o.points).any()]
    features = np.concatenate([o.points for o in near]) if near else np.zeros((0, 3))
    return [(near[c], features) for c in _chunks(len(near), CHUNK_OUTLINES)]


def chains(cv, sampling, st, region, part, rng):
    """Strokes started from a part's feature chains (ending at a distance from all the
    chains near the region)."""
    outlines, features = part
    if not outlines:
        return []
    return L.chain_strokes(cv.ev, outlines, cv.eye, cv.light, STEP * cv.unit, rng, features=features,
                           every=st.chain_step, angle=st.chain_angle, field=st.chain_field, axis=st.hatch_axis,
                           max_distance=st.chain_distance * cv.unit, lower=st.shade_lower,
                           upper=st.shade_upper, **_common(cv, st, region))


def short(cv, sampling, st, region, part):
    """Short strokes through a part's marks."""
    kw = _common(cv, st, region)
    paths = _kept(cv, region, st.hatch_field, "short", st.hatch_field, tuple(st.hatch_axis),
                  tuple(sorted(kw["weights"].items())), STEP * cv.unit)
    return L.short_strokes(cv.ev, part, cv.eye, cv.light, STEP * cv.unit, field=st.hatch_field,
                           axis=st.hatch_axis, lower=st.shade_lower, upper=st.shade_upper + 0.05, paths=paths,
                           every_path=cv.settled, **kw)


def stipples(cv, sampling, st, region, part, drawn=(), spacing=None, lines=()):
    """Stipples from a part's wandering smarticles, apart from each other and from the
    dots the parts before kept (``spacing``, strokes.stipples.Spacing) and drew
    (``drawn``), and finer where they come near the ``lines`` drawn (the visible
    outlines: a StrokeSet, whose outline layers count, or strokes)."""
    if hasattr(lines, "layers"):
        lines = [s for name in OUTLINE_LAYERS for s in lines.layers.get(name, ())]
    step = 0.5 * STEP * cv.unit
    return SP.stipples(cv.ev, part, cv.eye, cv.light, step, every=st.stipple_every,
                      lower=0.8 * st.shade_lower, upper=0.92 * st.shade_upper, radius=STIPPLE_RADIUS * cv.radius(st),
                      region=region, contrast=st.contrast, paths=_kept(cv, region, "dir1", "stipples", step),
                      every_path=cv.settled, drawn=drawn, spacing=spacing, sight=cv.sight, lines=lines)


def single_stroke(cv, st, point, seed=0):
    """One smarticle stroke from the surface point nearest ``point``, or None when the
    point is too far from the surface to project onto it (or the stroke would be a
    single point). It sets off along the flow field the way that goes to the right of
    the view (a principal direction has no way of its own)."""
    ev = cv.ev
    P, f, _ = project(ev, np.asarray(point, float).reshape(1, 3), steps=8, max_step=0.05 * ev.scale)
    if not on_surface(f, ev.iso, NEAR_SURFACE)[0]:
        return None
    field = L.direction_field(st.hatch_field, st.hatch_axis, cv.eye)
    H = L.headings(ev, P, st.hatch_field, view_right(cv.eye, P[0])[None], st.hatch_axis, cv.eye)
    res = sm.run(ev, P, field, STEP * cv.unit, st.resolved_weights(),
                 sm.StrokeRules(max_steps=SINGLE_STEPS, stop_on_curvature_sign=False), np.array([seed], np.uint64),
                 headings=H)
    p = res.paths[0]
    if len(p) < 2:
        return None
    r = cv.radius(st)
    return Stroke(p, np.full(len(p), r), np.ones(len(p)))
