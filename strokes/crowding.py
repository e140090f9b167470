"""Hatching that does not crowd on the paper. Lines of curvature of one family run
together (on a round lobe a whole fan of them meets at its pole), and near a silhouette
foreshortening packs a fan tighter still: drawn at full strength, the strokes of one
hatching layer burst into a star there. A stroke that comes, on the paper, within a gap
of strokes before it in the order that head other ways than it and than each other (a
knot) is drawn finer and lighter from there on, as an artist's pen lifts where a line
runs into lines already drawn, and ends in the knot's heart: the fan thins out towards
its centre. A stroke crossing strokes that all head one way is drawn whole (a crossing,
however many lines cross there), strokes that run alongside each other never thin each
other, and the cross-hatching is a layer of its own.

The thinning is a continuous function of where the strokes lie on the paper, and the
order is the strokes' marks' (model.keyed): as the view turns a stroke fades in and out
of a knot instead of coming or going at once."""
from dataclasses import replace

import numpy as np

from ..blackboard.board import pairs_within
from ..model import keyed

ORDER = 6                # which of two strokes that meet gives way (a salt, model.keyed)
CROWD_GAP = 0.5          # stroke units on the paper: strokes closer than this meet ...
CROWD_ANGLE = 15.0       # ... when their directions on the paper differ by more than this many degrees
KNOT = 1.0               # how much spread of the strokes met (see _knots) thins a point to nothing


class Crowding:
    """The strokes a layer drew so far, over its parts, as the eye sees them: a part's
    strokes thin out where they run into a knot of strokes before them (the parts
    before come first, then the marks' order)."""

    def __init__(self, eye, centre, gap):
        """``gap``: CROWD_GAP in model units (stroke units times the canvas's unit),
        measured on the paper at the model's ``centre``."""
        self.eye = np.asarray(eye, float)
        self.gap = float(gap)
        self.reach = float(np.linalg.norm(np.asarray(centre, float) - self.eye)) or 1.0
        # the probes drawn so far (their places on the paper, directions, owners, and the
        # probes before and after them on their strokes: themselves at an end)
        self.points, self.directions = np.zeros((0, 3)), np.zeros((0, 3))
        self.owners, self.count = np.zeros(0, np.int64), 0     # ... and how many owners so far
        self.before, self.after = np.zeros(0, np.int64), np.zeros(0, np.int64)

    def thinned(self, strokes):
        """The strokes, each point's radius and opacity times the least that the knots
        leave (:func:`_knots`: 1 outside any, 0 in a knot's heart) of it and of the
        points before it on its stroke: a stroke ends where that comes to nothing, and
        one left with fewer than two points is dropped. The strokes as they came (their
        whole paths) thin the strokes after them, here and in the parts to come."""
        if not strokes:
            return []
        sizes = np.array([len(s.points) for s in strokes])
        at = np.cumsum(sizes) - sizes
        P = np.concatenate([np.asarray(s.points, float).reshape(-1, 3) for s in strokes])
        local = np.arange(len(P)) - np.repeat(at, sizes)
        # every other point of each stroke, and its last, stand for it (a point between two
        # of them takes their mean; a stroke met is the polyline through its probes)
        probe = (local % 2 == 0) | (local == np.repeat(sizes, sizes) - 1)
        Q = self._on_paper(P)
        T = _directions(Q, at, sizes)
        T = T - np.einsum("ij,ij->i", T, Q)[:, None] * Q / self.reach ** 2     # across the line of sight
        T /= np.maximum(np.linalg.norm(T, axis=1), 1e-300)[:, None]
        owner, place = _owners(strokes)
        stroke = np.repeat(np.arange(len(strokes)), sizes)[probe]
        own = owner[stroke]                                                # each probe's owner
        Q, T = Q[probe], T[probe]
        n = len(Q)
        first = np.r_[True, stroke[1:] != stroke[:-1]]
        last = np.r_[stroke[1:] != stroke[:-1], True]
        before = np.where(first, np.arange(n), np.arange(n) - 1)
        after = np.where(last, np.arange(n), np.arange(n) + 1)
        # the probes within the gap, and their segments: a segment that passes within the gap
        # with both ends beyond it (its probes about a gap apart) would weigh little
        i0, j0 = pairs_within(Q, self.points, self.gap)
        i1, j1 = pairs_within(Q, Q, self.gap)
        later = place[own[j1]] < place[own[i1]]
        i1, j1 = i1[later], j1[later]
        # the strokes met, heading another way: the earlier parts', then this part's before in the order
        i = np.concatenate([i0, i1])
        D = np.concatenate([self.directions[j0], T[j1]])
        way = _another_way(np.einsum("ij,ij->i", T[i], D))
        some = (way > 0) & (np.einsum("ij,ij->i", T[i], T[i]) > 0.5) & (np.einsum("ij,ij->i", D, D) > 0.5)
        i, D, way, j0, j1 = i[some], D[some], way[some], j0[some[:len(j0)]], j1[some[len(j0):]]
        whose = np.concatenate([self.owners[j0], own[j1] + self.count])
        gone = np.concatenate([_to_polyline(Q[i[:len(j0)]], self.points, self.before, self.after, j0),
                               _to_polyline(Q[i[len(j0):]], Q, before, after, j1)])
        near = np.clip(1.0 - gone ** 2 / self.gap ** 2, 0.0, 1.0)
        left = np.ones(len(P))
        left[probe] = _knots(n, self._basis(Q), i, whose, D, near * near * way)
        between = np.flatnonzero(~probe)
        left[between] = 0.5 * (left[between - 1] + left[between + 1])
        out = []
        for s, a, k in zip(strokes, at, sizes):
            f = np.minimum.accumulate(left[a:a + k])         # the pen does not come back
            end = int(np.count_nonzero(f))                   # it ends where it fades to nothing
            if end < 2:
                continue
            out.append(s if np.all(f == 1.0) else replace(s, points=s.points[:end], radius=s.radius[:end] * f[:end],
                                                         opacity=s.opacity[:end] * f[:end], cyclic=False))
        m = len(self.points)
        self.points = np.vstack([self.points, Q])
        self.directions = np.vstack([self.directions, T])
        self.owners = np.concatenate([self.owners, own + self.count])
        self.before = np.concatenate([self.before, before + m])
        self.after = np.concatenate([self.after, after + m])
        self.count += int(owner.max()) + 1
        return out

    def _basis(self, Q):
        """Two directions across the line of sight to the strokes' middle (the paper's x and y)."""
        view = np.mean(Q, axis=0)
        view /= np.linalg.norm(view)
        x = np.cross(view, [0.0, 0.0, 1.0] if abs(view[2]) < 0.9 else [1.0, 0.0, 0.0])
        x /= np.linalg.norm(x)
        return x, np.cross(view, x)

    def _on_paper(self, P):
        """Points as the eye sees them: their directions from it, at the model's distance
        (so a distance between two is one on the paper, in model units at the model)."""
        V = P - self.eye
        return V / np.linalg.norm(V, axis=1)[:, None] * self.reach


def _to_polyline(X, Q, before, after, j):
    """Each point X[k]'s distance to the two segments of its stroke's probe polyline
    that meet at probe j[k] (Q: the probes; before, after: each probe's neighbours)."""
    return np.minimum(_to_segment(X, Q[before[j]], Q[j]), _to_segment(X, Q[j], Q[after[j]]))


def _to_segment(X, A, B):
    """Distances from points X to segments AB (a point where A is B)."""
    AB = B - A
    t = np.clip(np.einsum("ij,ij->i", X - A, AB) / np.maximum(np.einsum("ij,ij->i", AB, AB), 1e-300), 0.0, 1.0)
    return np.linalg.norm(X - (A + t[:, None] * AB), axis=1)


def _owners(strokes):
    """Each stroke's owner (the strokes of one mark, as the visible runs of one path are,
    share one: they never thin each other) and each owner's place in the order, by the
    number its mark's key draws (highest first)."""
    if any(s.mark is None for s in strokes):
        raise ValueError("hatching strokes thin each other by their marks: a stroke has none")
    keys, owner = np.unique(np.array([s.mark for s in strokes], np.uint64), return_inverse=True)
    place = np.empty(len(keys), np.int64)
    place[np.lexsort((np.arange(len(keys)), -keyed.uniform(keys, ORDER)))] = np.arange(len(keys))
    return owner.reshape(-1), place


def _another_way(cos):
    """How much a stroke met heads another way than the point's own, from the cosine of
    their angle: 0 within CROWD_ANGLE, 1 past twice that, smoothly between."""
    a, b = np.sin(np.radians(CROWD_ANGLE)) ** 2, np.sin(np.radians(2 * CROWD_ANGLE)) ** 2
    t = np.clip((1.0 - cos * cos - a) / (b - a), 0.0, 1.0)
    return t * t * (3 - 2 * t)


def _knots(n, basis, points, owners, directions, weights):
    """What of each of ``n`` points is drawn, from the strokes it meets: each stroke
    (``owners``) once per point (``points``), by its heaviest ``weights`` (how near it
    comes, 1 on the point and 0 at the gap, and how much it heads another way) and
    ``directions`` there. Their spread is the sum of the weights
    less the length of the weighted sum of their doubled angles on the paper
    (``basis``): 0 for strokes that all head one way however many, about 2 for two
    strokes at right angles through the point; a point is drawn by 1 - spread / KNOT,
    at least 0."""
    if len(points) == 0:
        return np.ones(n)
    heaviest = np.lexsort((-weights, owners, points))
    points, owners, directions, weights = points[heaviest], owners[heaviest], directions[heaviest], weights[heaviest]
    first = np.ones(len(points), bool)
    first[1:] = (points[1:] != points[:-1]) | (owners[1:] != owners[:-1])
    points, directions, weights = points[first], directions[first], weights[first]
    x, y = directions @ basis[0], directions @ basis[1]
    r2 = np.maximum(x * x + y * y, 1e-300)
    c, s, w = np.zeros(n), np.zeros(n), np.zeros(n)
    np.add.at(c, points, weights * (x * x - y * y) / r2)             # the doubled angles, weighted
    np.add.at(s, points, weights * 2 * x * y / r2)
    np.add.at(w, points, weights)
    return np.clip(1.0 - (w - np.hypot(c, s)) / KNOT, 0.0, 1.0)


def _directions(Q, at, sizes):
    """Polylines' directions at their points (the points one polyline after the other,
    the first of each at ``at``, ``sizes`` of them): central differences inside,
    one-sided at the ends, zero for a single point."""
    nxt = np.minimum(np.arange(len(Q)) + 1, len(Q) - 1)
    prv = np.maximum(np.arange(len(Q)) - 1, 0)
    last = at + sizes - 1
    nxt[last] = last
    prv[at] = at
    return Q[nxt] - Q[prv]
