"""Hidden-line removal against the exact iso-surface (not the rough polygonisation).

A point is visible when the segment from it to the eye does not enter the solid
(f >= iso). Segments are marched in one batch: each starts a small offset off the
surface towards the eye, is clipped to the surface's box (blackboard.polygonise.
surface_box: outside it the field stays below iso), and is sampled at a fixed fraction
of the model's size (of another solid's own, where that is smaller). Strokes are split
where visibility changes and the hidden parts dropped; each visible run ends where its
line really goes behind the surface, found by bisecting the step between its last
visible point and the next hidden one (so a line that passes behind another meets it,
not a step short of it). A line's own grazing surface hides a point or two of it where
the ray leaves the surface almost along it: such a short gap, hit within GRAZE
marching steps of its start, between visible points of the same line, is not a gap
for an outline (another solid hit first is); for a tone mark it is (visible_marks).
"""
from typing import NamedTuple

import numpy as np

from ..blackboard.polygonise import surface_box
from ..model.projection import project
from ..model.tolerances import on_surface


MARCH_BATCH = 4096          # points a ray-march call aims at
MAX_AHEAD = 32              # samples of one ray a call takes at most
GRAZE = 3                   # a hit within this many marching steps of a ray's start may be the line's own
                            # grazing surface
GRAZE_POINTS = 2            # ... and a gap of at most this many such points between visible ones is drawn through
FINE = 0.5              # a tone mark's rays are marched at this share of the step (a mark is small: a thin
                        # sliver of the model in front of it hides it; and it need not run on through a graze)
END_HALVINGS = 5            # bisections of the step where a visible run ends (to 1/32 of the step)
ONTO_STEPS = 4              # Newton steps that put such an end, on the step's chord, onto the surface
CHORD_HALVINGS = 4          # ... halving its share of the step where they cannot (beside a sharp wedge)


class Run(NamedTuple):
    """A visible run of a polyline: its points a..b-1, and how far the line stays
    visible into the step before a (``lead``) and after b-1 (``trail``), as shares of
    those steps (0: it goes behind the surface at the point itself), with the surface
    points there (``head``, ``tail``; None where the share is 0)."""
    a: int
    b: int
    lead: float = 0.0
    trail: float = 0.0
    head: object = None
    tail: object = None


class Sight:
    """What hides a model's lines from the eye: the model's own solid (``ev``, an
    evaluator) and the other solids of its scene (``others``: (evaluator, matrix) each,
    the 4x4 matrix taking a point of the model's coordinates into that solid's)."""

    def __init__(self, ev, others=()):
        self.ev = ev
        self.others = tuple((o, np.asarray(M, float)) for o, M in others)

    def solids(self):
        """(evaluator, matrix or None for the model's own coordinates) of every solid."""
        return ((self.ev, None),) + self.others


def sight_of(x):
    """A :class:`Sight` as given, or the sight of an evaluator's own solid alone."""
    return x if isinstance(x, Sight) else Sight(x)


def piece(values, run):
    """The values (normals, radii, ...) of a polyline along a :class:`Run`: rows
    a..b-1, with the values where the run really begins and ends interpolated into the
    steps before and after them."""
    V = np.asarray(values)
    head = V[run.a] + run.lead * (V[run.a - 1] - V[run.a]) if run.lead > 0 else None
    tail = V[run.b - 1] + run.trail * (V[run.b] - V[run.b - 1]) if run.trail > 0 else None
    return _between(head, V[run.a:run.b], tail)


def run_points(P, run):
    """The points of a polyline along a :class:`Run`: its points, and the surface
    points where the run really begins and ends."""
    return _between(run.head, np.asarray(P)[run.a:run.b], run.tail)


def _between(head, mid, tail):
    if head is None and tail is None:
        return mid
    parts = [np.asarray(x, mid.dtype).reshape((1,) + mid.shape[1:]) for x in (head, tail) if x is not None]
    return np.concatenate(([parts.pop(0)] if head is not None else []) + [mid] + parts)


def _clip(O, D, lo, hi):
    """Parameter range [t0, t1] of rays O + t D (t in [0, 1]) inside the box."""
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = 1.0 / D
        ta = (lo - O) * inv
        tb = (hi - O) * inv
    tmin = np.nanmax(np.where(np.isfinite(np.minimum(ta, tb)), np.minimum(ta, tb), -np.inf), axis=1)
    tmax = np.nanmin(np.where(np.isfinite(np.maximum(ta, tb)), np.maximum(ta, tb), np.inf), axis=1)
    inside_axis = (D == 0) & ((O < lo) | (O > hi))
    tmax = np.where(inside_axis.any(axis=1), -1.0, tmax)
    return np.maximum(tmin, 0.0), np.minimum(tmax, 1.0)


def visible(sight, P, eye, normals=None, step=None, offset=None):
    """Boolean visibility of points P (n,3) seen from eye (``sight``: a :class:`Sight`,
    or a model's evaluator alone)."""
    return ~np.isfinite(hits(sight, P, eye, normals, step, offset))


def march_step(ev):
    """The distance between a ray's samples (and its start's offset off the surface)."""
    return 2e-3 * ev.scale


def hits(sight, P, eye, normals=None, step=None, offset=None):
    """How far along the segment from each point P (n,3) of the model towards the eye,
    from its start (``offset`` off the surface), the first sample inside any solid of
    ``sight`` (a :class:`Sight`, or the model's evaluator alone) is: inf where none is
    (the point is visible). Distances and steps are in the model's coordinates."""
    return np.min(hits_each(sight, P, eye, normals, step, offset), axis=0)


def hits_each(sight, P, eye, normals=None, step=None, offset=None):
    """:func:`hits` of each solid of ``sight`` apart, the model's own first: (solids, n)."""
    sight = sight_of(sight)
    P = np.asarray(P, float)
    if len(P) == 0:
        return np.zeros((len(sight.solids()), 0))
    step = step if step is not None else march_step(sight.ev)
    offset = offset if offset is not None else march_step(sight.ev)
    to_eye = eye - P
    dist = np.linalg.norm(to_eye, axis=1)
    u = to_eye / dist[:, None]
    start = P + offset * u
    if normals is not None:
        start = start + 0.5 * offset * np.asarray(normals)
    D = eye - start
    length = np.linalg.norm(D, axis=1)
    out = []
    for ev, M in sight.solids():
        S, E = (start, D) if M is None else (start @ M[:3, :3].T + M[:3, 3], D @ M[:3, :3].T)
        # another solid is sampled at its own size's step where that is finer (a thin one
        # beside a big model is not stepped over), in the model's units
        own = step if M is None else min(step, march_step(ev) / max(np.linalg.norm(M[:3, :3], 2), 1e-300))
        out.append(_first_inside(ev, S, E, own / length) * length)
    return np.array(out)


def first_hits(ev, eye, D, step):
    """Where rays from ``eye`` along unit directions D (n, 3) first meet ev's solid,
    sampled ``step`` apart (the first sample inside: within a step past the surface),
    and which rays meet it."""
    box = surface_box(ev)
    lo, hi = box if box is not None else ev.bounds
    far = float(np.linalg.norm(np.asarray(eye, float) - 0.5 * (np.asarray(lo) + np.asarray(hi)))
                + np.linalg.norm(np.asarray(hi) - np.asarray(lo)))
    start = np.broadcast_to(np.asarray(eye, float), np.shape(D)).copy()
    t = _first_inside(ev, start, far * np.asarray(D, float), np.full(len(D), step / far))
    hit = np.isfinite(t)
    return start + np.where(hit, t, 0.0)[:, None] * far * np.asarray(D, float), hit


def _first_inside(ev, start, D, dt):
    """The parameter t (of start + t D, t in [0, 1]) of each ray's first sample inside
    ev's solid, the samples dt apart from where the ray enters the solid's box: inf
    where none is."""
    box = surface_box(ev)                           # where f >= iso can be (else the support's)
    lo, hi = box if box is not None else ev.bounds
    t0, t1 = _clip(start, D, lo, hi)
    at = np.full(len(start), np.inf)
    live = np.flatnonzero(t1 > t0)
    k = 0
    while len(live):
        # the samples k, k+1, ... of each ray still marching, as many per ray as keep a
        # batch near MARCH_BATCH points (a call's cost is mostly its own: the last few
        # rays take their remaining samples in a few calls, not one call per sample)
        b = int(np.clip(MARCH_BATCH // len(live), 1, MAX_AHEAD))
        t = t0[live, None] + (k + np.arange(b))[None, :] * dt[live, None]      # (m, b)
        inside = t <= t1[live, None]
        Q = (start[live, None, :] + t[:, :, None] * D[live, None, :]).reshape(-1, 3)
        if inside.all():                   # a sample a ray (always so when they take one each)
            f = ev.field(Q).reshape(t.shape)
        else:                              # the samples past a ray's end (its last call's tail) are not evaluated
            f = np.full(t.shape, -np.inf)
            f[inside] = ev.field(Q[inside.reshape(-1)])
        hit = f >= ev.iso
        got = hit.any(axis=1)
        rows = np.flatnonzero(got)
        at[live[rows]] = t[rows, hit[rows].argmax(axis=1)]
        live = live[~got & inside[:, -1]]
        k += b
    return at


def split_visible(sight, stroke_points, eye, normals=None, min_points=2):
    """The visible runs (:class:`Run`) of a polyline (``sight``: a :class:`Sight`, or the
    model's evaluator alone)."""
    return split_visible_many(sight, [stroke_points], eye, None if normals is None else [normals], min_points)[0]


def split_visible_many(sight, polylines, eye, normals=None, min_points=2):
    """The visible runs of many polylines, marched as one batch (one field evaluation
    per ray-march step for all their points): a list of :class:`Run` s per polyline."""
    if not polylines:
        return []
    sizes = np.array([len(p) for p in polylines])
    P = np.concatenate([np.asarray(p, float).reshape(-1, 3) for p in polylines])
    Nn = None if normals is None else np.concatenate([np.asarray(n, float).reshape(-1, 3) for n in normals])
    return visible_runs(sight, P, sizes, eye, Nn, min_points)


def tone_step(sight):
    """The step a tone mark's rays are marched at (FINE of the usual)."""
    return FINE * march_step(sight_of(sight).ev)


def visible_runs(sight, P, sizes, eye, normals=None, min_points=2, grazes=True, step=None):
    """:func:`split_visible_many` of polylines given as their points one after the other
    (``P``, with their ``normals``) and their lengths (``sizes``); without ``grazes`` a
    short gap at the line's own grazing surface is a gap too (a tone mark is no outline:
    it need not run on through it), ``step``: the rays' (default march_step)."""
    sight = sight_of(sight)
    sizes = np.asarray(sizes, np.int64)
    each = hits_each(sight, P, eye, normals, step)
    d = each.min(axis=0)
    if grazes:              # a graze is the model's own surface, hit before any other solid
        v = _through_grazes(np.isfinite(d), (each[0] <= GRAZE * march_step(sight.ev)) & (each[0] <= d), sizes)
    else:
        v = ~np.isfinite(d)
    return _ends(sight, P, normals, eye, _runs(v, sizes, min_points), np.cumsum(sizes) - sizes, sizes,
                 None if grazes else step)


def visible_marks(sight, P, sizes, eye, normals):
    """The visible runs of tone marks (:func:`visible_runs`): a graze of the surface is a
    gap, the rays marched at the tone marks' step (:func:`tone_step`)."""
    return visible_runs(sight, P, sizes, eye, normals, grazes=False, step=tone_step(sight))


def _through_grazes(hidden, grazed, sizes):
    """Visibility (not ``hidden``) with each gap of at most GRAZE_POINTS hidden points
    that are all ``grazed``, between visible points of its own polyline, drawn through."""
    v = ~hidden
    line = np.repeat(np.arange(len(sizes)), sizes)
    local = np.arange(len(v)) - np.repeat(np.cumsum(sizes) - sizes, sizes)
    d = np.diff(np.concatenate([[0], hidden.astype(np.int8), [0]]))
    starts, ends = np.flatnonzero(d == 1), np.flatnonzero(d == -1)
    if len(starts) == 0:
        return v
    far = np.concatenate([[0], np.cumsum(~grazed)])
    inner = (line[starts] == line[ends - 1]) & (local[starts] > 0) & (local[ends - 1] < sizes[line[starts]] - 1)
    fill = inner & (ends - starts <= GRAZE_POINTS) & (far[ends] == far[starts])
    for a, b in zip(starts[fill].tolist(), ends[fill].tolist()):
        v[a:b] = True
    return v


def _ends(sight, P, normals, eye, runs, first, sizes, check=None):
    """The runs (per polyline, index ranges) as :class:`Run` s, each end that meets a
    hidden point of its polyline moved to where the line goes behind the surface: the
    step between the two is bisected END_HALVINGS times (on the chord, the normals
    interpolated), all ends in one batch; with ``check`` (a step), an end that the move
    onto the surface took out of sight again is not moved."""
    P = np.asarray(P, float)
    N = None if normals is None else np.asarray(normals, float)
    ends = []                              # (polyline, run, 0 lead / 1 trail, visible index, hidden index)
    for k, rs in enumerate(runs):
        for j, (a, b) in enumerate(rs):
            if a > 0:
                ends.append((k, j, 0, first[k] + a, first[k] + a - 1))
            if b < sizes[k]:
                ends.append((k, j, 1, first[k] + b - 1, first[k] + b))
    out = [[Run(a, b) for a, b in rs] for rs in runs]
    if not ends:
        return out
    E = np.array(ends, np.int64)
    vis, hid = E[:, 3], E[:, 4]
    lo, hi = np.zeros(len(E)), np.ones(len(E))         # shares of the step from the visible point
    for _ in range(END_HALVINGS):
        s = 0.5 * (lo + hi)
        Q = P[vis] + s[:, None] * (P[hid] - P[vis])
        Nq = None
        if N is not None:
            Nq = N[vis] + s[:, None] * (N[hid] - N[vis])
            Nq /= np.maximum(np.linalg.norm(Nq, axis=1, keepdims=True), 1e-300)
        seen = visible(sight, Q, eye, Nq)
        lo, hi = np.where(seen, s, lo), np.where(seen, hi, s)
    X, lo = _onto_chord(sight.ev, P[vis], P[hid], lo)
    if check is not None:
        Nx = None if N is None else N[vis]
        lo = np.where(visible(sight, X, eye, Nx, step=check), lo, 0.0)
    for (k, j, side, _, _), s, x in zip(ends, lo.tolist(), X):
        if s > 0:
            out[k][j] = out[k][j]._replace(trail=s, tail=x) if side else out[k][j]._replace(lead=s, head=x)
    return out


def _onto_chord(ev, A, B, s):
    """Points at shares ``s`` of the chords from A to B (surface points) put onto the
    surface: projected off the chord's sag; where that does not reach the surface (a
    point beside a sharp wedge, where Newton stalls between its sheets) the share is
    halved, nearer A, up to CHORD_HALVINGS times, and else 0 (A itself). Returns the
    points and their shares."""
    s = np.array(s, float)
    X = np.array(A, float)
    live = np.flatnonzero(s > 0)
    for _ in range(CHORD_HALVINGS + 1):
        if len(live) == 0:
            break
        Q, f, _ = project(ev, A[live] + s[live, None] * (B[live] - A[live]), ONTO_STEPS)
        on = on_surface(f, ev.iso)
        X[live[on]] = Q[on]
        live = live[~on]
        s[live] *= 0.5
    s[live] = 0.0
    return X, s


def _runs(v, sizes, min_points):
    """[(start, end)] of the True runs of v at least min_points long, per polyline
    (``sizes``: the polylines' lengths along v; a run never crosses from one to the
    next), found in one pass over all of them."""
    ends_at = np.cumsum(sizes)
    first = ends_at - sizes
    # a False between consecutive polylines, so no run crosses from one into the next
    gap = np.insert(v.astype(np.int8), ends_at, 0)
    gapped = first + np.arange(len(sizes))                   # each polyline's first point in ``gap``
    d = np.diff(np.concatenate([[0], gap, [0]]))
    starts, ends = np.flatnonzero(d == 1), np.flatnonzero(d == -1)
    keep = ends - starts >= min_points
    starts, ends = starts[keep], ends[keep]
    line = np.searchsorted(gapped, starts, "right") - 1
    starts, ends = (starts - gapped[line]).tolist(), (ends - gapped[line]).tolist()
    out = [[] for _ in sizes]
    for k, a, b in zip(line.tolist(), starts, ends):
        out[k].append((a, b))
    return out
