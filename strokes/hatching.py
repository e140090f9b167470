"""Hatching that gives the tone the light asks for (strokes.tone), drawn from the
model's hatching map (strokes.hatch_map: nested sets of evenly spaced lines fixed on the
model, Praun et al. 2001's tonal art maps laid on the surface): each point of a line as
wide as its tone asks of its level, the newest level ramping in (:func:`widths`); and
what every layer of lines shares (:class:`Layer`: the light, the tone's share, the
lines' widths and spacing on the paper, the outlines that end them).
"""
from dataclasses import dataclass, field

import numpy as np

from . import tone as TN
from ..blackboard.cells import pairs_within
from ..model import keyed
from ..model.vectors import tangents
from .data import Stroke
from ..model.projection import project
from ..model.tolerances import NEAR_SURFACE, on_surface
from .visibility import ONTO_STEPS, piece, run_points, visible_marks

THINNEST = 0.35          # at contrast 1 the lines of the lightest tone have this share of the darkest's width
SPARSEST = 40.0         # line widths: the spacing of the lightest lines, at most
TURNING = 0.08          # a line ends where the surface turns this far from the eye (the cosine of n and the view)
SHORTEST = 4            # points: a line (a grown one, a part of one left in sight, one shortened at crowded
                        # ends) cut shorter is a scrap ...
TICK = 2                # ... but every piece of a map's line, between where its tone, the facing surface, the
                        # region, the line or a visible outline ends it, is drawn from this long: a small patch
                        # of shade crossed in a step gets its short mark
EDGE = 0.5              # steps: a piece that ends in a step where its tone ends runs on this far into it
SLIM = 4.0              # a mark (or the part of one in sight) is drawn if this many times as long as it is wide
                        # on the paper (a shorter one, seen end on or mostly hidden, reads as a blot)


def width(t, radius, contrast):
    """A line's width (twice its radius) at tone ``t``: ``radius`` at the darkest, down to
    THINNEST of it in the lightest at contrast 1."""
    return 2.0 * radius * (1.0 - float(contrast) * (1.0 - THINNEST) * (1.0 - TN.darkness(t)))


def spacing(t, share, radius, contrast):
    """How far apart (in model units, across the line of sight) one layer's lines stand
    at tone ``t``: their width over their coverage; inf where the layer draws nothing
    (no coverage, or lines sparser than SPARSEST base widths would give)."""
    c = TN.coverage(t, share)
    w = width(t, radius, contrast)
    with np.errstate(divide="ignore"):
        d = np.where(c > 0, w / np.maximum(c, 1e-300), np.inf)
    return np.where(d <= SPARSEST * 2 * radius, d, np.inf)


@dataclass
class Layer:
    """What one hatching layer is drawn with: the model's evaluator, the paper, the light
    (strokes.tone.Shadows), what hides the lines (a strokes.visibility.Sight), the tone curve
    (``lower``, ``upper``, ``contrast``), the lines' ``radius`` at the darkest, the
    ``share`` of the tone it gives (strokes.tone.coverage), the smarticles' ``flow`` field and first ``headings``
    (functions of points and normals, and of those and marks' reference directions),
    their ``step``, ``weights`` and ``rules`` (strokes.smarticles), the visible outlines
    (strokes) that end lines, the lines drawn (:class:`Lines`), how many smarticles
    set off from each seed side by side (a flock), and how far from the eye the surface
    may turn before a line ends (the cosine of the normal and the view)."""
    ev: object
    paper: object
    shadows: object
    sight: object
    lower: float
    upper: float
    contrast: float
    radius: float
    share: str
    flow: object
    headings: object
    step: float
    weights: dict
    rules: object
    outlines: list = field(default_factory=list)
    drawn: object = None                 # strokes.paper.Placed: the lines grown (chains) or the lines' ends
                                         # (hatching, its crossing layer's with them) on the paper so far
    flock_size: int = 1
    turning: float = TURNING

    def tone(self, P, N):
        return TN.tone(self.shadows.light(P, N), self.lower, self.upper, self.contrast)

    def spacing(self, t):
        return spacing(t, self.share, self.radius, self.contrast)


def _turning(paper, P, N, turning=TURNING):
    V = paper.eye - np.asarray(P, float)
    return np.einsum("ij,ij->i", N, V) <= turning * np.linalg.norm(V, axis=1)


def _outline_segments(layer):
    """A test of which steps (their ends' places on the paper) cross a visible outline."""
    segs = []
    for s in layer.outlines:
        p = np.asarray(s.points, float)
        if s.cyclic and len(p) > 2:
            p = np.vstack([p, p[:1]])
        if len(p) > 1:
            q, _ = layer.paper.place(p)
            segs.append(np.column_stack([q[:-1, :2], q[1:, :2]]))
    S = np.concatenate(segs) if segs else np.zeros((0, 4))
    C, D = S[:, 0:2], S[:, 2:4]
    mid = np.column_stack([0.5 * (C + D), np.zeros(len(S))])
    half = 0.5 * np.linalg.norm(D - C, axis=1).max() if len(S) else 0.0

    def crossing(A, B):
        out = np.zeros(len(A), bool)
        if len(S) == 0 or len(A) == 0:
            return out
        a, b = A[:, :2], B[:, :2]
        m = np.column_stack([0.5 * (a + b), np.zeros(len(a))])
        i, j = pairs_within(m, mid, half + 0.5 * np.linalg.norm(b - a, axis=1).max() + 1e-12)
        if len(i):
            r, s = b[i] - a[i], D[j] - C[j]
            den = r[:, 0] * s[:, 1] - r[:, 1] * s[:, 0]
            q = C[j] - a[i]
            with np.errstate(divide="ignore", invalid="ignore"):
                u = (q[:, 0] * s[:, 1] - q[:, 1] * s[:, 0]) / den
                v = (q[:, 0] * r[:, 1] - q[:, 1] * r[:, 0]) / den
            hit = (den != 0) & (u >= 0) & (u <= 1) & (v >= 0) & (v <= 1)
            out[i[hit]] = True
        return out
    return crossing


FRAY_SALT = 13          # where a line too thin for its tone's width is drawn at the thinnest (a salt, model.keyed)


def draw(layer, hmap, lines=None, gain=None):
    """A frame's hatching from a hatching map (strokes.hatch_map) of the lines ``lines``
    (numbers; default all): each point of a line drawn as wide as the tone wants of its
    level (:func:`widths`, the coverage asked scaled by ``gain``, a strokes.density.Gain),
    the lines split where they leave the tone, turn from the eye, leave the region, cross
    a visible outline or go out of sight, and shortened where their ends would crowd
    (:func:`spread_ends`, in the map's order: lower levels, then longer lines, first; the
    ends of the parts drawn before in ``layer.drawn``)."""
    out, owner = marks(layer, hmap, lines, gain)
    return spread_ends(layer.paper, out, owner, 2.0 * layer.radius, layer.drawn)


def marks(layer, hmap, lines=None, gain=None):
    """:func:`draw`'s marks before their ends are spread, and the line each is of."""
    which = np.arange(len(hmap)) if lines is None else np.asarray(lines, np.int64)
    sizes = hmap.sizes()[which]
    rows = np.concatenate([np.arange(a, a + n) for a, n in zip(hmap.start[which], sizes)]) if len(which) else \
        np.zeros(0, np.int64)
    if len(rows) == 0:
        return [], np.zeros(0, np.int64)
    P, N = hmap.points[rows], hmap.normals[rows]
    line = np.repeat(which, sizes)
    first = np.cumsum(sizes) - sizes
    local = np.arange(len(P)) - np.repeat(first, sizes)
    T = tangents(P, first, sizes)
    facing = ~_turning(layer.paper, P, N)
    w, scale = widths(layer, hmap, P, N, T, hmap.level[line], hmap.key[line], hmap.spread[rows], facing, gain)
    inside = np.ones(len(P), bool) if layer.rules.region is None else layer.rules.region.contains(P)
    drawn = (w > 0) & inside
    crossing = _outline_segments(layer)
    q = layer.paper.place(P)[0]
    cut = np.zeros(len(P), bool)                        # a step into the point crosses a visible outline
    inner = local > 0
    cut[inner] = crossing(q[np.flatnonzero(inner) - 1], q[inner])
    runs = _runs(drawn, cut, first, sizes)
    if not runs:
        return [], np.zeros(0, np.int64)
    RP, RN, r, psizes = _to_the_edges(layer, P, N, 0.5 * w / scale, drawn, facing & inside, cut, first, sizes,
                                      runs)
    out, owner = [], []
    at = np.cumsum(psizes) - psizes
    for k, vis in enumerate(visible_marks(layer.sight, RP, psizes, layer.paper.eye, RN)):
        for run in vis:
            whole = run.a == 0 and run.b == psizes[k]           # (a part of a run in sight is a scrap below SHORTEST)
            run = run._replace(a=at[k] + run.a, b=at[k] + run.b)
            pts = run_points(RP, run)
            if len(pts) < (TICK if whole else SHORTEST):
                continue
            rad = piece(r, run)
            xy, sc = layer.paper.place(pts)
            if slim(xy, 2.0 * rad * sc):
                out.append(Stroke(pts, rad, np.ones(len(pts)), mark=int(hmap.key[line[runs[k][0]]])))
                owner.append(line[runs[k][0]])
    return out, np.asarray(owner, np.int64)


END_REACH = 6.0         # widest line widths: within this of any line end on the paper ...
END_MOST = 4            # ... lie at most this many ends of the hatching's lines (more read as a blot, or a fan)


def spread_ends(paper, strokes, rank, widest, drawn):
    """The strokes, taken in ``rank`` order (lower first), each shortened from an end
    (point by point) while that end would make more than END_MOST ends within END_REACH
    widest line widths of it or of an end taken before (this part's, or the parts'
    before: ``drawn``, a strokes.paper.Placed of the layer's line ends, added to), on
    the paper; left out where that leaves it shorter than SHORTEST (or than itself, a
    short mark). Lines that run into a corner or a seam of the field end one after
    another, not in one blot."""
    E, R = drawn.places[:, :2], drawn.reach                # two ends are near within the smaller of their reaches
    count = np.zeros(len(E), np.int64)
    if len(E):
        i, j = pairs_within(drawn.places, drawn.places, R.max())
        count = np.bincount(i[np.linalg.norm(E[i] - E[j], axis=1) < np.minimum(R[i], R[j])], minlength=len(E))

    def crowds(x, reach):
        near = np.linalg.norm(E - x, axis=1) < np.minimum(R, reach)
        return near.sum() + 1 > END_MOST or (count[near] + 1 > END_MOST).any(), near

    out, ends = [], []
    for k in np.argsort(rank, kind="stable").tolist():
        s = strokes[k]
        xy, scale = paper.place(s.points)
        reach = END_REACH * widest * scale
        a, b = 0, len(xy)
        least = max(TICK, min(SHORTEST, b))
        while b - a >= least and crowds(xy[a, :2], reach[a])[0]:
            a += 1
        while b - a >= least and crowds(xy[b - 1, :2], reach[b - 1])[0]:
            b -= 1
        if b - a < least:
            continue
        for end in (a, b - 1):
            near = crowds(xy[end, :2], reach[end])[1]
            count[near] += 1
            E, R, count = np.vstack([E, xy[end, :2]]), np.append(R, reach[end]), np.append(count, near.sum() + 1)
            ends.append((xy[end], reach[end]))
        out.append(s if (a, b) == (0, len(xy)) else
                   Stroke(s.points[a:b], s.radius[a:b], s.opacity[a:b], s.cyclic, s.dots, s.mark))
    if ends:
        drawn.add(np.array([x for x, _ in ends]), np.array([r for _, r in ends]))
    return out


def widths(layer, hmap, P, N, T, level, key, spread=None, facing=None, gain=None):
    """How wide (on the paper) each point of a map's lines is drawn, and the paper's scale
    there. Level 0's lines stand ``hmap.spacing`` apart on the surface, so S0 = spacing
    times how far apart the paper sets lines a unit apart on the surface (square to
    them); a line is at most W = the layer's widest (twice its ``radius``) on the paper. The tone's coverage c wants
    lines of width c S0 at level 0; where that exceeds W the levels come in one by one:
    at lam = log2(c S0 / W) between m and m + 1 the levels up to m are drawn W wide and
    level m + 1 (2^(lam - m) - 1) W wide, so that the coverage is c and grows smoothly;
    past the last level every line widens. A line thinner than THINNEST of W is drawn
    THINNEST W wide where its key's number says (as often as its width asks), else not.
    With the map's ``spread`` at the points (strokes.hatch_map.spread) the coverage asked
    of a line is scaled by how far apart the lines of its set really stand there, so
    that lines crowded together thin and lines far apart widen (or bring the next
    level in sooner), and the tone stays even; with a ``gain`` (strokes.density.Gain)
    it is scaled by the gain at the point's place on the paper."""
    facing = ~_turning(layer.paper, P, N) if facing is None else facing
    t = np.zeros(len(P))
    t[facing] = layer.tone(P[facing], N[facing])
    c = TN.coverage(t, layer.share)
    q, scale = layer.paper.place(P)
    if gain is not None:
        c = c * gain.at(q)
    eps = 1e-3 * hmap.spacing
    a = layer.paper.place(P + eps * np.cross(N, T))[0] - q      # a step across the line and one along it, on
    along = layer.paper.place(P + eps * T)[0] - q               # the paper: lines a spacing apart stand apart
    tn = np.linalg.norm(along, axis=1)                          # by its part square to the line there
    gap = np.where(tn > 1e-9 * eps, np.abs(a[:, 0] * along[:, 1] - a[:, 1] * along[:, 0]) / np.maximum(tn, 1e-300),
                   np.linalg.norm(a, axis=1))
    stretch = gap / eps / np.maximum(scale, 1e-300)
    W = 2.0 * layer.radius * scale
    S0 = hmap.spacing * stretch * scale
    last = hmap.levels - 1
    with np.errstate(divide="ignore"):
        lam = np.log2(np.maximum(c * S0, 1e-300) / W)
    if spread is not None:
        full = np.clip(np.nan_to_num(np.ceil(lam) - 1), 0, last).astype(np.int64)   # the set drawn full width there
        with np.errstate(divide="ignore"):
            lam = np.log2(np.maximum(c * S0 * spread[np.arange(len(P)), full], 1e-300) / W)
    m = np.clip(np.ceil(lam) - 1, 0, last)
    w = np.where(level <= m, W, np.where(level == m + 1, (np.exp2(lam - m) - 1.0) * W, 0.0))
    w = np.where(lam <= 0, np.where(level == 0, c * S0, 0.0), w)
    w = np.where(lam > last, np.exp2(lam - last) * W, w)        # past the last level: wider
    thin = THINNEST * W
    u = keyed.uniform(np.asarray(key, np.uint64), FRAY_SALT)
    w = np.where(w < thin, np.where(u * thin < w, thin, 0.0), w)
    return np.where(facing & (c > 0), w, 0.0), scale


def _to_the_edges(layer, P, N, radius, drawn, open_to, cut, first, sizes, runs):
    """The runs' points one after the other, with their normals and radii, each run
    carried on EDGE of a step beyond an end where the next point of its line is not drawn
    but faces the eye, lies in the region and is reached without crossing a visible
    outline: its tone ends in that step (on average halfway), and a run that stopped at
    its last point inside would leave half a step's ink out at each end (a step in all:
    half the ink of a patch of shade two steps across). The new end is put onto the
    surface and drawn as wide as the end it carries on. ``open_to``: which points face
    the eye (as :func:`widths` found) and lie in the region. Returns the points, normals,
    radii and the runs' sizes."""
    A, B = np.array([a for a, _ in runs]), np.array([b for _, b in runs])
    start, stop = np.repeat(first, sizes), np.repeat(first + sizes, sizes)
    open_ = open_to & ~drawn
    head = (A - 1 >= start[A]) & open_[np.maximum(A - 1, 0)] & ~cut[A]
    tail = (B < stop[B - 1]) & open_[np.minimum(B, len(P) - 1)] & ~cut[np.minimum(B, len(P) - 1)]
    ends = np.concatenate([A[head], B[tail] - 1])
    beyond = np.concatenate([A[head] - 1, B[tail]])
    hx, tx = {}, {}
    if len(ends):
        X, f, g = project(layer.ev, P[ends] + EDGE * (P[beyond] - P[ends]), ONTO_STEPS)
        onto = on_surface(f, layer.ev.iso, NEAR_SURFACE)
        Nx = -g / np.maximum(np.linalg.norm(g, axis=1, keepdims=True), 1e-300)
        heads = int(head.sum())
        for i, k in enumerate(np.concatenate([np.flatnonzero(head), np.flatnonzero(tail)])):
            if onto[i]:
                (hx if i < heads else tx)[int(k)] = (X[i], Nx[i])
    pts, nrm, rad, n = [], [], [], []
    for k, (a, b) in enumerate(runs):
        p, m, r = [P[a:b]], [N[a:b]], [radius[a:b]]
        if k in hx:
            p.insert(0, hx[k][0][None]), m.insert(0, hx[k][1][None]), r.insert(0, radius[a:a + 1])
        if k in tx:
            p.append(tx[k][0][None]), m.append(tx[k][1][None]), r.append(radius[b - 1:b])
        pts += p
        nrm += m
        rad += r
        n.append(sum(len(x) for x in p))
    return np.concatenate(pts), np.concatenate(nrm), np.concatenate(rad), np.array(n)


def slim(xy, widths):
    """Whether a mark through these places on the paper, this wide at them, is at least
    SLIM times as long as it is wide (a shorter one reads as a blot)."""
    return bool(np.linalg.norm(np.diff(np.asarray(xy)[:, :2], axis=0), axis=1).sum() >= SLIM * np.max(widths))


def _runs(drawn, cut, first, sizes):
    """The (start, end) rows of the drawn runs of each line, split where a step crosses
    an outline, at least TICK points long: a small patch of shade (a vein's flank, a
    strip of a face between two windows) crossed in a step gets its short mark."""
    go = drawn.copy()
    brk = np.zeros(len(go) + 1, bool)
    brk[first] = True
    brk[np.flatnonzero(cut)] = True
    out = []
    d = np.diff(np.concatenate([[0], go.astype(np.int8), [0]]))
    starts, ends = np.flatnonzero(d == 1), np.flatnonzero(d == -1)
    for a, b in zip(starts.tolist(), ends.tolist()):
        # split at line starts and cuts inside [a, b)
        inner = np.flatnonzero(brk[a + 1:b]) + a + 1
        bounds = [a] + inner.tolist() + [b]
        for x, y in zip(bounds[:-1], bounds[1:]):
            if y - x >= TICK:
                out.append((x, y))
    return out
