"""A session that goes on from the last frame's (the future work of MASSRIS: agents that
re-sample only where the surface changes over time).

A finished session leaves a :class:`Continuation`: its model, view and settings, its
outlines, and the field-only part of its initialisation (the rough polygonisation and
the blackboard it filled, before any feature point), which the next frame's session
takes as it is where the model is the same. The next session (:func:`carried`):

- keeps as traced the last frame's outlines outside the parts of space where the field
  changed (agents.changes): the creases and curvature-sign lines there, and the
  silhouettes and suggestive contours too where the eye stayed where it was
  (blackboard.board.VIEW_DEPENDENT);
- follows the silhouettes there when the eye moved (agents.follow: every point moved
  onto this frame's silhouette in one batch) and seeds the parts it could not follow,
  and the suggestive contours, from the last frame's points: every SEED_EVERY-th point
  brackets across the outline, BRACKETS cells to either side, refined onto this
  frame's outline as the polygon edges' seeds are (an outline that moved further is
  found from the polygon edges, as in a first frame);
- looks afresh where the field changed, as in a first frame (everything when the
  tree's shape changed);
- looks for the features smaller than a cell (the detail phase) only where the field
  changed (the last frame's small outlines elsewhere are among its seeds), but in every
  REFRESH-th frame everywhere: a small silhouette that a moving eye brings into view is
  found within REFRESH frames;
- with the same model, checks the last frames' explorers' walks (:class:`Walks`) for
  silhouettes seen from this eye instead, and explores only the voxels no walk explored:
  a small silhouette a moving eye brings into view where a walk went is found at once.
"""
import copy
from dataclasses import dataclass, field

import numpy as np

from ..blackboard.board import VIEW_DEPENDENT
from ..blackboard.keys import unique_rows
from ..model.vectors import cross
from .changes import EVERYWHERE, changed
from .outline import Outline

SEED_EVERY = 3           # points of a last frame's outline from one seed to the next
BRACKETS = (0.08, 0.3)   # a seed's brackets reach these many cells to either side of the outline: a
                         # wider one holds an outline that moved further, a narrower one a smaller
                         # one (a bracket over a bend of more than half the crease angle is refused)
REFRESH = 8              # every REFRESH-th frame going on from the last looks for small features everywhere
# settings under which a last frame's outlines are this frame's (the grid may differ)
SAME_OUTLINES = ("kinds", "crease_angle", "tolerance", "step", "subdivide", "explore_detail")


@dataclass(frozen=True)
class Init:
    """The field-only part of a session's initialisation: the rough polygonisation, the
    blackboard it filled (never changed: a session works on its own copy), the vertices'
    curvature and the grid resolution."""
    mesh: object
    board: object
    curvature: dict
    resolution: int

    def board_copy(self):
        return copy.deepcopy(self.board)


@dataclass(frozen=True)
class Walks:
    """The explorers' walks over one model, from every frame that saw it (the pairs of
    points each walk compared, with their normals) and the voxel rows they explored. A
    silhouette smaller than a cell that a moved eye brings into view where a walk went
    flips the sign of n.v between a pair's points: found again with no field evaluation,
    and those voxels need no explorer again."""
    A: np.ndarray
    nA: np.ndarray
    B: np.ndarray
    nB: np.ndarray
    rows: frozenset = frozenset()

    def joined(self, pairs, rows):
        """These walks and a session's (pairs: A, nA, B, nB; rows: the voxels explored)."""
        return Walks(*(np.concatenate([a, b]) for a, b in zip((self.A, self.nA, self.B, self.nB), pairs)),
                     self.rows | frozenset(rows))

    def silhouette_brackets(self, view):
        """The pairs (a, b) between whose points n.v changes sign, seen from ``view``."""
        flip = (np.einsum("ij,ij->i", self.nA, view.towards_eye(self.A)) > 0) != \
            (np.einsum("ij,ij->i", self.nB, view.towards_eye(self.B)) > 0)
        return self.A[flip], self.B[flip]

    def seeds(self, view, board, lost):
        """Silhouette seeds on ``board`` (a session's blackboard) where these walks cross a
        silhouette seen from ``view``, away from the voxels of the ``lost`` outlines
        (their own seeds find them): their ids. Before the outlines a session keeps or
        follows are added, so that those crossing them are taken as theirs
        (agents.traced.consume_crossed), as any seed is; :func:`thin_walk_seeds` then
        thins the rest."""
        a, b = self.silhouette_brackets(view)
        mid = 0.5 * (a + b)
        if lost and len(mid):
            near = board.voxel_rows(board.voxel_of(np.concatenate([o.points for o in lost])), create=False)
            nb = board.neighbours(np.unique(near[near >= 0]))
            ok = ~np.isin(board.voxel_rows(board.voxel_of(mid), create=False), nb[nb >= 0])
            a, b, mid = a[ok], b[ok], mid[ok]
        return board.add_features(mid, a, b, "silhouette")


NO_WALKS = Walks(*(np.zeros((0, 3)) for _ in range(4)))


@dataclass(frozen=True)
class Continuation:
    """What a finished session leaves the next frame's."""
    model: object                  # model.nodes.Model
    view: tuple                    # blackboard.view.View.key(): where the eye was
    settings: object               # agents.session.Settings
    outlines: tuple                # agents.outline.Outline, stitched
    init: Init = None
    age: int = 0                   # frames since a session looked for small features everywhere
    complete: bool = True          # the session ran to its end (not to a time or iteration budget)
    walks: Walks = None            # its explorers' walks and the last frames' with the same model (with init)
    swept: frozenset = frozenset()  # the voxel rows it and the last frames looked in for untraced silhouettes
                                    # (agents.detail.unfound_silhouettes; with init)


@dataclass
class Carried:
    """What a session takes from the last frame's: its initialisation (or None), the
    outlines it keeps as traced (``whole``: those kept as they were, which its own
    outlines include as they are, not stitched again; ``kept``: the parts of the others
    where the field did not change), those it seeds from, and where the field changed
    (None: nowhere; EVERYWHERE; or agents.changes.Boxes)."""
    init: object = None
    whole: list = field(default_factory=list)
    kept: list = field(default_factory=list)
    seeds: list = field(default_factory=list)
    changed: object = EVERYWHERE
    age: int = 0                   # frames since the detail phase last looked everywhere (0: this one does)
    same_eye: bool = False         # the eye is where the last frame's was
    walks: Walks = None            # the explorers' walks of the last frames with this model (with init)
    complete: bool = False         # the last frame's session ran to its end: its creases and curvature-sign
                                   # lines where the field is the same are all there are
    swept: frozenset = frozenset()  # the voxel rows the last frames with this model looked in for untraced
                                    # silhouettes (with init; none every REFRESH-th frame): their lines are
                                    # followed, not looked for again


def carried(previous, model, view, settings):
    """What a session of ``model`` seen in ``view`` (its key) takes from ``previous`` (a
    Continuation or None: then nothing, and everything counts as changed)."""
    if previous is None or any(getattr(previous.settings, k) != getattr(settings, k) for k in SAME_OUTLINES):
        return Carried()
    region = changed(previous.model, model)
    same_eye = previous.view == view
    init = previous.init if region is None and previous.init is not None and \
        previous.init.resolution == settings.resolution else None
    age = previous.age + 1
    out = Carried(init=init, changed=region, age=0 if age >= REFRESH else age, complete=previous.complete,
                  same_eye=same_eye, walks=previous.walks if init is not None else None,
                  swept=previous.swept if init is not None and age < REFRESH else frozenset())
    if region is EVERYWHERE:
        return out                      # as from scratch
    for o in previous.outlines:
        inside = np.zeros(len(o.points), bool) if region is None else region.contains(o.points)
        # where the field changed, the agents look afresh (polygon edges, the detail phase);
        # elsewhere what did not move is kept, and the lines a moved eye sees go on from here
        # (the session follows the silhouettes and seeds the rest)
        keeps = o.kind not in VIEW_DEPENDENT or same_eye
        kept = out.kept if keeps else out.seeds
        if not inside.any():
            (out.whole if keeps else kept).append(o)
            continue
        for a, b, outside in _runs(~inside, o.closed):
            if outside:
                rows = np.arange(a, b) % len(o.points)
                kept.append(Outline(o.kind, o.points[rows], o.normals[rows], False, o.step))
    return out


def _runs(keep, closed):
    """(start, end, value) runs of a boolean array; a closed outline's last run and first
    run join when they have the same value (rolled: indices may pass the end)."""
    n = len(keep)
    edges = np.flatnonzero(keep[1:] != keep[:-1]) + 1
    starts = np.r_[0, edges]
    ends = np.r_[edges, n]
    runs = [(int(a), int(b), bool(keep[a])) for a, b in zip(starts, ends)]
    if closed and len(runs) > 1 and runs[0][2] == runs[-1][2]:
        a, _, v = runs.pop()
        first = runs.pop(0)
        runs.append((a, n + first[1], v))
    return [(a, b, v) for a, b, v in runs]


def thin_walk_seeds(board, traced, ids, away):
    """Of the walks' seeds ``ids`` (Walks.seeds) still open, those at least ``away`` from
    every traced silhouette point (agents.traced.TracedPoints), one a half voxel; the
    others are taken."""
    ids = ids[~board.feat["used"][ids]]
    mid = board.feat["pos"][ids]
    ok = traced.unknown("silhouette", mid, away)
    _, first = unique_rows(np.floor(mid[ok] / (0.5 * board.h)).astype(np.int64), return_index=True)
    keep = np.zeros(len(ids), bool)
    keep[np.flatnonzero(ok)[first]] = True
    board.consume(ids[~keep])


def seed_brackets(outlines, h):
    """Brackets (a, b) and kinds of seeds along outlines: every SEED_EVERY-th point,
    segments across the outline in its tangent plane, BRACKETS * h to either side."""
    A, B, K = [], [], []
    for o in outlines:
        P, N = np.asarray(o.points, float), np.asarray(o.normals, float)
        if len(P) < 2:
            continue
        T = np.gradient(np.vstack([P[-1:], P, P[:1]]) if o.closed else P, axis=0)
        T = T[1:-1] if o.closed else T
        W = cross(N, T)
        W /= np.maximum(np.linalg.norm(W, axis=1, keepdims=True), 1e-300)
        sel = slice(SEED_EVERY // 2, len(P), SEED_EVERY)
        for width in BRACKETS:
            d = width * h * W[sel]
            A.append(P[sel] - d)
            B.append(P[sel] + d)
            K += [o.kind] * len(d)
    if not A:
        return np.zeros((0, 3)), np.zeros((0, 3)), []
    return np.concatenate(A), np.concatenate(B), K
