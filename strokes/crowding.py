"""Hatching that does not crowd on the paper. Lines of curvature of one family run
together at an umbilic (on a round lobe a whole fan of them meets at one point), and
near a silhouette foreshortening packs a fan tighter still: drawn whole, the strokes
of one hatching layer burst into a star there. A stroke stops where it comes closer on
the paper than a gap to strokes before it in the order that head other ways than it
and than each other, as an artist lifts the pen where a line would run into a knot of
lines already drawn; the fan thins out towards its centre instead. A stroke crossing
other strokes that all head one way goes on (a crossing, however many lines cross
there), strokes that run alongside each other never stop each other, and the
cross-hatching is a layer of its own.

The order is the strokes' marks' (model.keyed: the same from frame to frame), so a
stroke only stops where the picture has a meeting of strokes, and the same one stops
in the next frame."""
from dataclasses import replace

import numpy as np

from ..blackboard.board import pairs_within
from ..model import keyed

ORDER = 6                # which of two strokes that meet stops (a salt, model.keyed)
CROWD_GAP = 0.35         # stroke units on the paper: two strokes closer than this meet ...
CROWD_ANGLE = 15.0       # ... when their directions on the paper differ by more than this many degrees


class Crowding:
    """The strokes a layer drew so far, over its parts, as the eye sees them: a part's
    strokes stop where they run into a knot of strokes before them (the parts before
    come first, then the marks' order)."""

    def __init__(self, eye, gap):
        """``gap``: CROWD_GAP in model units (stroke units times the canvas's unit)."""
        self.eye = np.asarray(eye, float)
        self.gap = float(gap)
        self.reach = None                     # the distance the paper is measured at (the first part's)
        self.points, self.directions = np.zeros((0, 3)), np.zeros((0, 3))
        self.owners, self.count = np.zeros(0, np.int64), 0     # whose each point is, and how many owners so far

    def cut(self, strokes):
        """The strokes, each ending before the first point where it meets strokes that
        come before it heading several ways (:func:`_knots`); a stroke left with fewer
        than two points is dropped. The strokes' whole paths stop others (not what is
        left of them). The ones drawn are kept here for the parts to come."""
        if not strokes:
            return []
        sizes = np.array([len(s.points) for s in strokes])
        P = np.concatenate([np.asarray(s.points, float).reshape(-1, 3) for s in strokes])
        if self.reach is None:
            self.reach = float(np.median(np.linalg.norm(P - self.eye, axis=1)))
        Q = self._on_paper(P)
        T = np.concatenate([_directions(Q[a:a + n]) for a, n in zip(np.cumsum(sizes) - sizes, sizes)])
        T = T - np.einsum("ij,ij->i", T, Q)[:, None] * Q / self.reach ** 2     # across the line of sight
        T /= np.maximum(np.linalg.norm(T, axis=1), 1e-300)[:, None]
        across = np.cos(np.radians(CROWD_ANGLE))
        owner, place = _owners(strokes)
        stroke = np.repeat(np.arange(len(strokes)), sizes)
        s_of = owner[stroke]                                    # each point's owner
        # the strokes before it that each point meets (heading another way), and their directions
        i0, j0 = pairs_within(Q, self.points, self.gap)
        k = np.abs(np.einsum("ij,ij->i", T[i0], self.directions[j0])) < across
        i1, j1 = pairs_within(Q, Q, self.gap)
        meet = (place[s_of[j1]] < place[s_of[i1]]) & (np.abs(np.einsum("ij,ij->i", T[i1], T[j1])) < across)
        blocked = _knots(len(P), np.concatenate([i0[k], i1[meet]]),
                         np.concatenate([self.owners[j0[k]], s_of[j1[meet]] + self.count]),
                         np.concatenate([self.directions[j0[k]], T[j1[meet]]]), self._basis(Q))
        out, keep = [], np.zeros(len(P), bool)
        for k, (a, n) in enumerate(zip(np.cumsum(sizes) - sizes, sizes)):
            stop = np.flatnonzero(blocked[a:a + n])
            end = int(stop[0]) if len(stop) else int(n)
            if end >= 2:
                st = strokes[k]
                out.append(st if end == n else replace(st, points=st.points[:end], radius=st.radius[:end],
                                                       opacity=st.opacity[:end], cyclic=False))
                keep[a:a + end] = True
        self.points = np.vstack([self.points, Q[keep]])
        self.directions = np.vstack([self.directions, T[keep]])
        self.owners = np.concatenate([self.owners, s_of[keep] + self.count])
        self.count += int(s_of.max()) + 1
        return out

    def _basis(self, Q):
        """Two directions across the line of sight to the strokes' middle (the paper's x and y)."""
        view = np.mean(Q, axis=0)
        view /= np.linalg.norm(view)
        x = np.cross(view, [0.0, 0.0, 1.0] if abs(view[2]) < 0.9 else [1.0, 0.0, 0.0])
        x /= np.linalg.norm(x)
        return x, np.cross(view, x)

    def _on_paper(self, P):
        """Points as the eye sees them: their directions from it, at the distance of the
        first part's strokes (so a distance between two is one on the paper, in model
        units near the model)."""
        V = P - self.eye
        return V / np.linalg.norm(V, axis=1)[:, None] * self.reach


def _owners(strokes):
    """Each stroke's owner (the strokes of one mark, as the visible runs of one path are,
    share one: they never stop each other) and each owner's place in the order, by the
    number its mark's key draws (highest first; a stroke without a mark is its own
    owner, its index its key)."""
    keys = np.array([s.mark if s.mark is not None else k for k, s in enumerate(strokes)], np.uint64)
    own = np.array([s.mark is not None for s in strokes])
    tagged = np.where(own, keys, np.uint64(0))
    _, owner = np.unique(np.stack([tagged, np.where(own, 0, np.arange(len(strokes)) + 1).astype(np.uint64)]),
                         axis=1, return_inverse=True)
    owner = owner.reshape(-1)
    key_of = np.zeros(owner.max() + 1, np.uint64)
    key_of[owner] = keys
    place = np.empty(len(key_of), np.int64)
    place[np.lexsort((np.arange(len(key_of)), -keyed.uniform(key_of, ORDER)))] = np.arange(len(key_of))
    return owner, place


def _knots(n, points, owners, directions, basis):
    """Which of ``n`` points meet strokes heading more than one way: the strokes
    (``owners``) each point (``points``) meets, once each, with their ``directions``
    (3D, across the line of sight), spread over more than CROWD_ANGLE (the mean of
    their doubled angles on the paper, ``basis``, is shorter than the cosine of the
    angle: two lines that far apart, or more lines spread wider)."""
    if len(points) == 0:
        return np.zeros(n, bool)
    _, first = np.unique(np.stack([points, owners]), axis=1, return_index=True)
    points, directions = points[first], directions[first]
    x, y = directions @ basis[0], directions @ basis[1]
    r2 = np.maximum(x * x + y * y, 1e-300)
    c, s = np.zeros(n), np.zeros(n)
    np.add.at(c, points, (x * x - y * y) / r2)               # cos and sin of the doubled angle
    np.add.at(s, points, 2 * x * y / r2)
    count = np.bincount(points, minlength=n)
    return (count >= 2) & (np.hypot(c, s) < np.cos(np.radians(CROWD_ANGLE)) * count)


def _directions(Q):
    """A polyline's direction at each of its points (zero for a single point)."""
    return np.gradient(Q, axis=0) if len(Q) > 1 else np.zeros((len(Q), 3))
