"""Outlines drawn twice: where a fold's contour runs along the model's rim, or two
outlines run side by side closer on the paper than about a line width, the two read as
one line drawn double (a blotted, wobbly line). Of two such strokes, an open one
leaves out its stretch along a closed one (a jug's mouth stays whole where the
shoulder's contour runs along it), and else the shorter its stretch along the longer
(at least MIN_RUN points: a crossing or a T-junction is no doubling); the other keeps
the line."""
import numpy as np

from ..blackboard.cells import pairs_within
from .data import Stroke

DOUBLED = 1.5           # two outline strokes this many line widths apart on the paper, or closer, ...
PARALLEL = 0.9          # ... running alike (|cos| of the angle between them on the paper at least this) ...
MIN_RUN = 3             # ... over at least this many points of the shorter, are one line drawn twice
BRIDGE = 4              # points between two such stretches, at most, that go with them (no stub of a line)


def _seen(P, eye):
    """Points as the eye sees them: their directions from the eye (a paper round it),
    and their distances."""
    rel = np.asarray(P, float) - eye
    depth = np.linalg.norm(rel, axis=1)
    return rel / depth[:, None], depth


def doubled_points(strokes, eye):
    """For each stroke, which of its points lie along a stroke that outranks it (a closed
    one an open one, else a longer one, else one before it) closer than DOUBLED line
    widths on the paper, running alike."""
    eye = np.asarray(eye, float)
    if any(len(s.points) == 0 for s in strokes):          # (an empty stroke runs along nothing)
        some = [k for k, s in enumerate(strokes) if len(s.points)]
        got = dict(zip(some, doubled_points([strokes[k] for k in some], eye)))
        return [got.get(k, np.zeros(0, bool)) for k in range(len(strokes))]
    seen = [_seen(s.points, eye) for s in strokes]
    U = np.concatenate([u for u, _ in seen]) if strokes else np.zeros((0, 3))
    sizes = np.array([len(s.points) for s in strokes], np.int64)
    owner = np.repeat(np.arange(len(strokes)), sizes)
    first = np.cumsum(sizes) - sizes
    reach = np.concatenate([DOUBLED * 2.0 * np.asarray(s.radius, float) / d for s, (_, d) in zip(strokes, seen)]) \
        if strokes else np.zeros(0)
    out = [np.zeros(n, bool) for n in sizes]
    if len(U) < 2:
        return out
    seg = np.linalg.norm(np.diff(U, axis=0), axis=1)
    seg[np.cumsum(sizes)[:-1] - 1] = 0.0                 # (no segment from one stroke to the next)
    # (a rare long segment, a bridge across a gap, does not widen every point's search)
    i, j = pairs_within(U, U, float(reach.max() + np.percentile(seg, 99)))
    closed = np.array([s.cyclic for s in strokes], bool)
    rank = (sizes + closed * (sizes.max() + 1))[owner]
    longer = (rank[j] > rank[i]) | ((rank[j] == rank[i]) & (owner[j] < owner[i]))
    i, j = i[longer], j[longer]
    if len(i) == 0:
        return out
    # the direction at each point, along its stroke
    nxt = np.minimum(np.arange(len(U)) + 1, first[owner] + sizes[owner] - 1)
    prv = np.maximum(np.arange(len(U)) - 1, first[owner])
    T = U[nxt] - U[prv]
    T -= np.einsum("ij,ij->i", T, U)[:, None] * U
    T /= np.maximum(np.linalg.norm(T, axis=1, keepdims=True), 1e-300)
    # the segments at each point: a closed stroke's last point joins its first
    last = first[owner] + sizes[owner] - 1
    ring = np.array([s.cyclic for s in strokes], bool)[owner]
    at = np.arange(len(U))
    nxt_seg = np.where(ring & (at == last), first[owner], nxt)
    prv_seg = np.where(ring & (at == first[owner]), last, prv)
    hit = np.zeros(len(U), bool)
    for a, b in ((prv_seg[j], j), (j, nxt_seg[j])):       # the segments of the outranking stroke at j
        d = U[b] - U[a]
        t = np.clip(np.einsum("ij,ij->i", U[i] - U[a], d) / np.maximum(np.einsum("ij,ij->i", d, d), 1e-300), 0, 1)
        gap = np.linalg.norm(U[a] + t[:, None] * d - U[i], axis=1)
        alike = np.abs(np.einsum("ij,ij->i", T[i], d)) >= PARALLEL * np.linalg.norm(d, axis=1)   # (the segment's way)
        np.logical_or.at(hit, i[(gap <= reach[i]) & alike & (a != b)], True)
    return [hit[f:f + n] for f, n in zip(first, sizes)]


def undoubled(strokes, eye):
    """Each stroke with its stretches of at least MIN_RUN points that run along a stroke
    that outranks it (:func:`doubled_points`) left out (a stroke wholly along one goes,
    however short): per stroke, the list of what is left of it (itself, or its pieces
    of two points or more)."""
    out = []
    for s, hit in zip(strokes, doubled_points(strokes, eye)):
        if len(hit) == 0:                                  # an empty stroke draws nothing
            out.append([])
            continue
        drop = _runs_at_least(~_runs_at_least(~hit, BRIDGE + 1, s.cyclic, inner=True), MIN_RUN, s.cyclic)
        # what is kept reaches a point into each stretch left out: it meets the other line
        keep = ~drop
        near = keep | np.roll(keep, 1) | np.roll(keep, -1)
        if not s.cyclic:                                   # (no wrapping round an open line's ends)
            near[0], near[-1] = keep[0] | keep[min(1, len(keep) - 1)], keep[-1] | keep[max(len(keep) - 2, 0)]
        drop &= ~near
        out.append([])
        if not drop.any():
            out[-1].append(s)
            continue
        P, r, o = np.asarray(s.points), np.asarray(s.radius), np.asarray(s.opacity)
        idx = np.arange(len(P))
        if s.cyclic:                                       # start where a dropped stretch begins
            start = int(np.flatnonzero(drop & ~np.roll(drop, 1))[0]) if not drop.all() else 0
            idx = np.roll(idx, -start)
            idx = np.append(idx, idx[0])
        keep = ~drop[idx]
        edges = np.flatnonzero(np.diff(np.concatenate([[0], keep.astype(np.int8), [0]])))
        for a, b in zip(edges[::2], edges[1::2]):
            if b - a >= 2:
                k = idx[a:b]
                out[-1].append(Stroke(P[k], r[k], o[k], cyclic=False, dots=s.dots, mark=s.mark))
    return out


def _runs_at_least(hit, n, cyclic, inner=False):
    """The True runs of ``hit`` at least ``n`` long (round the end too, when cyclic), or
    all of it when all is True; with ``inner``, also every run that touches an end of an
    open line."""
    if hit.all() or not hit.any():
        return hit.copy()
    shift = int(np.argmin(hit)) if cyclic else 0
    h = np.roll(hit, -shift)
    edges = np.flatnonzero(np.diff(np.concatenate([[0], h.astype(np.int8), [0]])))
    out = np.zeros(len(h), bool)
    for a, b in zip(edges[::2], edges[1::2]):
        if b - a >= n or (inner and not cyclic and (a == 0 or b == len(h))):
            out[a:b] = True
    return np.roll(out, shift)
