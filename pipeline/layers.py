"""The stroke layers of a style, from a sampling session's plain result (agents.Sampling)
and the model's marks (model.marks): the visible outlines, hatching and cross-hatching,
strokes from the feature chains, short strokes, stipples, and a single stroke. One
function per layer; the illustration calls them in a fixed order, a layer in parts of
its starts (strokes.layers places them, strokes.smarticles moves them).

Every length of the strokes (a smarticle's step, the marks' spacing, how far chain
strokes go) is a multiple of the canvas's ``unit`` (framing.stroke_unit), which moving
the model or its parts does not change."""
import dataclasses
from dataclasses import dataclass, field

import numpy as np

from ..model import Evaluator, keyed
from ..model.curvature import curvature
from ..model.marks import surface_marks
from ..model.projection import project
from ..model.tolerances import NEAR_SURFACE, on_surface
from ..strokes import cross_field as CF
from ..strokes import density as DN
from ..strokes import hatch_map as HM
from ..strokes import grown as GR
from ..strokes import hatching as HT
from ..strokes import layers as L
from ..strokes import smarticles as sm
from ..strokes import stipples as SP
from ..strokes import tone as TN
from ..strokes.data import LAYER_OF_KIND, Stroke
from ..strokes.paper import Paper, Placed
from .framing import size as framing_size, surface_centre
from ..model.owners import owners
from ..strokes.style import outline_strokes, view_right
from ..strokes.visibility import Sight

OUTLINE_LAYERS = tuple(LAYER_OF_KIND.values())
CHAIN_TURN = np.radians(85.0)   # a stroke from a feature line ends where its normal has turned this far (from a
                                # silhouette, nearly to where the surface faces the eye)
STEP = 0.3                  # a smarticle's step, in stroke units (stipples take half)
STIPPLE_RADIUS = 1.8        # a stipple's radius, in line radii, at the darkest tone
SHADOW_REACH = 4.0          # how far a shadow's ray goes, in the model's support diagonals
CROSS_PEN = 0.7             # the crossing layer's widest line, a share of the hatching's
HATCH_RADIUS = 0.7          # a hatching line's radius, in line radii, at the darkest tone
ORDER = 11                  # the order of marks of one spacing (a salt, model.keyed)
CHAIN_SALT = 12             # the keys of the strokes started from the feature chains (a salt, model.keyed)
SHORT_STEPS = 3             # a short stroke's steps each way
SINGLE_STEPS = 60           # a single stroke's steps, at most
CHUNK = 1000                # starts per part of a stroke layer (one pipeline step each)
CHUNK_LINES = 500           # lines of a hatching map per part
CHUNK_OUTLINES = 40         # outlines per part of the chain strokes
# Hatching, short strokes and stipples start at marks on the model (model.marks); each
# layer its own set (a salt), at a spacing in stroke units.
MARKS = {"hatching": (0, 0.78),
         "field": (3, 0.5),           # the nodes of the hatching's cross field
         "short": (1, 0.78),
         "stipples": (2, 0.5)}        # a wandering smarticle draws several dots


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
    cache: dict = field(default_factory=dict, compare=False)     # what the layers share (shadows)

    def radius(self, st):
        """The radius of the style's lines."""
        return self.line_radius * st.line_width

    def paper(self):
        """Where the eye sees the model's points (strokes.paper.Paper), about its surface's
        centre (framing.surface_centre), which moves with the model."""
        return Paper(self.eye, surface_centre(self.ev))

    def shadows(self, seed):
        """The light's cast shadows on the model (strokes.tone.Shadows), found at the
        cross field's nodes once per illustration."""
        if "shadows" not in self.cache:
            nodes = field_nodes(self, seed)
            self.cache["shadows"] = TN.Shadows(self.seen_by(), nodes.points, nodes.normals, self.light,
                                               SHADOW_REACH * self.ev.scale, MARKS["field"][1] * self.unit)
        return self.cache["shadows"]

    def seen_by(self):
        """What hides the marks and casts shadows on them: the sight, or the model alone."""
        return self.ev if self.sight is None else self.sight


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


def _on_surface_kind(ev, P, st):
    """Whether points lie on the style's surface (convex or concave)."""
    mean = curvature(ev, P)["mean"]
    return mean > 0 if st.surface == "convex" else mean < 0


def starts(ev, marks, st, region):
    """The marks in the region and on the style's surface (all, convex or concave)."""
    keep = np.ones(len(marks), bool) if region is None else region.contains(marks.points)
    if st.surface != "all" and keep.any():
        keep[keep] = _on_surface_kind(ev, marks.points[keep], st)
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


def coarse_order(marks, spacing):
    """The order of marks by their sequences' spacing (model.marks: the first of each
    primitive's sequence are the coarsest cover of it), so that a layer drawn in parts
    covers the whole model coarsely first and fills in after."""
    u = keyed.uniform(marks.keys, ORDER)
    return np.lexsort((u, marks.index * spacing ** 2 / marks.area))


def ordered_parts(layer):
    """The parts of a line layer's marks, coarse ones first (:func:`coarse_order`)."""
    def parts(cv, sampling, marks, st, region):
        m = starts(cv.ev, marks, st, region)
        m = m.take(coarse_order(m, MARKS[layer][1] * cv.unit))
        return [m.take(c) for c in _chunks(len(m), CHUNK)]
    return parts


def field_nodes(cv, seed):
    """The marks that carry the cross field and tell the cast shadows: made once per model
    (kept with its evaluator, as the illustration keeps its layers' marks)."""
    key = ("marks", "field", seed, cv.unit)
    if key not in cv.ev.memo:
        cv.ev.memo[key] = marks_of(cv, "field", owners(cv.ev), seed)
    return cv.ev.memo[key]


def cross_field(cv, seed):
    """The model's smoothed cross field (strokes.cross_field), at its own marks: made once
    per model (kept with its evaluator, as the marks are)."""
    key = ("cross field", seed, cv.unit)
    if key not in cv.ev.memo:
        nodes = field_nodes(cv, seed)
        cv.ev.memo[key] = CF.CrossField(cv.ev, nodes.points, nodes.normals, MARKS["field"][1] * cv.unit,
                                        framing_size(cv.ev))
    return cv.ev.memo[key]


PRINCIPAL = {"dir1": (0.0, "dir1"), "dir2": (0.0, "dir2"), "diagonal": (45.0, "dir1")}   # (turn, line)


def _fields(cv, st, kind, seed):
    """The flow field and the first headings of a hatching layer along ``kind``: the
    principal kinds along the smoothed cross field (turned 45 degrees for the diagonal),
    a stroke keeping to the branch nearest its heading, setting off on the field's first
    line (dir1), the other (dir2) or between them (the diagonal); the others as
    strokes.layers.direction_field."""
    if kind not in PRINCIPAL:
        def heads(P, N, ref):
            return L.headings(cv.ev, P, kind, ref, st.hatch_axis, cv.eye)
        return L.direction_field(kind, st.hatch_axis, cv.eye), heads
    turn, want = PRINCIPAL[kind]
    field = cross_field(cv, seed)

    def cross(P, N, fallback):
        d = field.at(P, N, fallback)
        return CF.turned(d, N, turn) if turn else d

    def flow(P, N, c):
        return CF.branch(cross(P, N, c["velocity"]), N, c["velocity"])

    def heads(P, N, ref):
        if len(P) == 0:
            return np.zeros((0, 3))
        w = field.first_at(P, N, ref)
        w = np.cross(N, w) if want == "dir2" else w
        w = CF.turned(w, N, turn) if turn else w
        H = CF.branch(cross(P, N, w), N, w)
        s = np.sign(np.einsum("ij,ij->i", H, ref))
        return H * np.where(s == 0, 1.0, s)[:, None]
    return flow, heads


def _layer(cv, st, region, seed, share, fields, steps, lines, outlines, pen=1.0):
    """A line layer of marks (strokes.hatching.Layer) of the style: its ``share`` of the
    tone, its flow field and first headings (``fields``), its smarticles' ``steps`` each
    way, the ``lines`` its parts before drew and the visible ``outlines`` that end them
    (a StrokeSet, whose outline layers count, or strokes), its ``pen`` (a share of
    HATCH_RADIUS line radii: its widest line)."""
    if hasattr(outlines, "layers"):
        outlines = [s for name in OUTLINE_LAYERS for s in outlines.layers.get(name, ())]
    rules = sm.StrokeRules(max_steps=steps, region=region, stop_on_curvature_sign=st.surface != "all")
    flow, heads = fields
    return HT.Layer(cv.ev, cv.paper(), cv.shadows(seed), cv.seen_by(), st.shade_lower, st.shade_upper, st.contrast,
                    pen * HATCH_RADIUS * cv.radius(st), share, flow, heads, STEP * cv.unit, st.resolved_weights(),
                    rules, list(outlines), lines if lines is not None else Placed(), st.flock_size)


def hatch_map(cv, st, seed, cross=False, marks=None):
    """The hatching map (strokes.hatch_map) of the model for the style's hatching (or its
    crossing layer): made once per model and style (kept with its evaluator, as the
    marks are), seeded by the hatching's ``marks``; one that follows the contour
    direction is the eye's too."""
    kind = st.cross_field if cross else st.hatch_field
    w = st.resolved_weights()
    width = 2.0 * _pen(cross) * HATCH_RADIUS * cv.radius(st)
    key = ("hatch map", cross, kind, tuple(st.hatch_axis), st.hatch_steps, tuple(sorted(w.items())), st.flock_size,
           st.surface, seed, cv.unit, width, tuple(cv.eye) if kind == "contour" else None)
    if key not in cv.ev.memo:
        m = starts(cv.ev, marks, st, None)
        flow, heads = _fields(cv, st, kind, seed)
        levels = HM.levels_for(float(TN.coverage(TN.DARKEST, _share(st, cross))))
        cv.ev.memo[key] = HM.build(cv.ev, m, coarse_order(m, MARKS["hatching"][1] * cv.unit), flow, heads,
                                   STEP * cv.unit, st.hatch_steps, w, width,
                                   sm.StrokeRules(stop_on_curvature_sign=st.surface != "all"), st.flock_size,
                                   levels, None if st.surface == "all" else lambda P: _on_surface_kind(cv.ev, P, st))
    return cv.ev.memo[key]


def _pen(cross):
    """The pen of a hatching layer: the crossing layer's is finer (CROSS_PEN)."""
    return CROSS_PEN if cross else 1.0


def _share(st, cross):
    """The share of the tone a hatching layer gives (strokes.tone.coverage)."""
    return "rest" if cross else ("first" if st.cross_hatching else "all")


def map_parts(cross):
    """The parts of a hatching layer: its map's lines in chunks (the map made at the
    layer's first step)."""
    def parts(cv, sampling, marks, st, region, seed=0):
        n = len(hatch_map(cv, st, seed, cross, marks))
        return [np.arange(n)[c] for c in _chunks(n, CHUNK_LINES)]
    return parts


def hatching(cv, sampling, st, region, part, cross=False, lines=None, outlines=(), seed=0):
    """Hatching along the style's flow field (or, with ``cross``, the crossing layer along
    its cross field, the rest of the tone): a part's lines of the model's hatching map,
    each drawn as wide as its tone wants of its level (strokes.hatching.draw) and as the
    gain evens it out, ended at the visible ``outlines``. The gain (strokes.density) is
    measured once an illustration, at its first part, on the whole map drawn beside no
    outlines: a frame that goes on from the last traces them within their tolerance of
    a frame alone's, and its gain is the same."""
    layer = _layer(cv, st, region, seed, _share(st, cross), (None, None), st.hatch_steps, lines, outlines, _pen(cross))
    hmap = hatch_map(cv, st, seed, cross)
    key = ("hatch gain", cross, seed)
    if key not in cv.cache:
        bare = dataclasses.replace(layer, outlines=[])
        within = None if st.surface == "all" else lambda P: _on_surface_kind(cv.ev, P, st)
        cv.cache[key] = DN.measure(bare, hmap, HT.marks(bare, hmap)[0], within)
    return HT.draw(layer, hmap, part, cv.cache[key])


def chains_parts(cv, sampling, marks, st, region):
    near = [o for o in sampling.outlines if region is None or region.contains(o.points).any()]
    return [(k, near[c]) for k, c in enumerate(_chunks(len(near), CHUNK_OUTLINES))]


def chains(cv, sampling, st, region, part, lines=None, outlines=(), seed=0):
    """Strokes started from a part's feature chains (Smarticles 7.2): from every
    ``chain_step``-th point, at ``chain_angle`` to the chain along the chain field, into
    the visible side of a silhouette and both sides of a crease, as far as
    ``chain_distance``, spaced and ended as hatching is (and the seeds beside them fill
    the tone in)."""
    k, chunk = part
    P, N, H = L.off_the_chain(cv.ev, *L.chain_seeds(chunk, cv.eye, st.chain_step, st.chain_angle), 0.5 * STEP * cv.unit)
    keys = keyed.combine(np.full(len(P), seed, np.uint64), k, np.arange(len(P)), CHAIN_SALT)
    kind = st.chain_field
    fields = (L.direction_field(kind, st.hatch_axis, cv.eye), None)
    steps = max(1, int(round(st.chain_distance / STEP)))
    layer = _layer(cv, st, region, seed, "all", fields, steps, lines, outlines)
    layer = dataclasses.replace(layer, turning=0.0, rules=dataclasses.replace(layer.rules, max_normal_angle=CHAIN_TURN))
    return GR.grow(layer, P, N, H, keys, np.arange(len(P)))       # (from the silhouettes themselves)


def short(cv, sampling, st, region, part, lines=None, outlines=(), seed=0):
    """Short strokes through a part's marks (and the seeds beside them), spaced and ended
    as hatching is: the tone's rest over the stipples where the style draws both."""
    share = "rest" if st.stipples else "all"
    layer = _layer(cv, st, region, seed, share, _fields(cv, st, st.hatch_field, seed), SHORT_STEPS, lines, outlines)
    return GR.from_marks(layer, part, np.arange(len(part)))


def stipples(cv, sampling, st, region, part, dots=None, lines=(), seed=0):
    """Stipples from a part's wandering smarticles, apart on the paper from each other
    and from the dots the parts before drew (``dots``, strokes.paper.Placed), and finer
    where they come near the ``lines`` drawn (the visible outlines: a StrokeSet, whose
    outline layers count, or strokes)."""
    if hasattr(lines, "layers"):
        lines = [s for name in OUTLINE_LAYERS for s in lines.layers.get(name, ())]
    step = 0.5 * STEP * cv.unit
    return SP.stipples(cv.ev, part, cv.paper(), cv.shadows(seed), step, st.shade_lower, st.shade_upper, st.contrast,
                       radius=STIPPLE_RADIUS * cv.radius(st), every=st.stipple_every, region=region,
                       paths=_kept(cv, region, "dir1", "stipples", step), every_path=cv.settled, dots=dots,
                       sight=cv.sight, lines=lines, share="first" if st.short else "all")


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
