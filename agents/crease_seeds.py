"""Silhouettes that start on creases: a crease trace compares each step with the
previous one (identify feature points, MASSRIS section 6) and seeds a silhouette where
a sheet's normal turns from facing the eye to facing away. Where overlapping parts meet
(a locomotive's wheels) such silhouette arcs end at creases at both ends, and the rough
polygonisation's edges may cross none of them."""
import numpy as np

from ..blackboard.board import KIND_ID
from .steering import unit

OFFSET = 0.15       # seeds lie this many steps into their sheet (a silhouette meeting the
                    # crease obliquely still crosses the seed bracket); the two sheets'
                    # seeds are told apart by their normals (TracedPoints.near)


def sides(view, X, A, B, nA, nB):
    """Side records of crease points X from their bracket ends A, B and the two sheets'
    normals there: (X, side directions (k, 2, 3), side facings (k, 2))."""
    W = unit(B - A)                                   # from side A towards side B
    facing = np.stack([np.einsum("ij,ij->i", nA, view.towards_eye(A)),
                       np.einsum("ij,ij->i", nB, view.towards_eye(B))], axis=1)
    return X, np.stack([-W, W], axis=1), facing


def flips(before, now, d):
    """Seed brackets (a, b, row) for silhouettes leaving a crease between two of its
    points, for rows of side records ``before`` and ``now``: the sheets are matched by
    their side directions, and where a sheet's facing changed sign the bracket runs d
    (per row) into that sheet at both points; side A's before side B's in each row."""
    x0, dirs0, facing0 = before
    x1, dirs1, facing1 = now
    k = len(x0)
    same = np.einsum("ij,ij->i", dirs0[:, 0], dirs1[:, 0]) >= 0
    side = np.array([0, 1])
    old = np.where(same[:, None], side[None, :], 1 - side[None, :])            # (k, 2)
    rows = np.arange(k)[:, None]
    flip = (facing0[rows, old] > 0) != (facing1 > 0)
    r, c = np.nonzero(flip)                                                    # row-major: side A first
    o = old[r, c]
    a = x0[r] + d[r, None] * dirs0[r, o]
    b = x1[r] + d[r, None] * dirs1[r, c]
    return a, b, r


def seed_sides(surface, X, A, B):
    """The side records of new crease seeds (their sheets' normals from one batched
    evaluation at the bracket ends)."""
    _, g = surface.field_grad(np.concatenate([A, B]))
    n = surface.normals(g)
    return sides(surface.view, X, A, B, n[:len(X)], n[len(X):])


def off_creases(view, kinds, X, A, B, nA, nB, ok, has_sides, before, base):
    """After a trace step, for the crease tasks among ``kinds`` (each task's new point
    X, its bracket ends A, B and their normals, whether it is ``ok``, whether it has
    side records and those records ``before``, and its trace step ``base``): the seed
    brackets (a, b) of silhouettes that start on the creases between each task's last
    and current point, the task each came from, and the rows whose side records are
    now ``now`` (the caller keeps them)."""
    rows = np.flatnonzero((kinds == KIND_ID["crease"]) & ok)
    rows = rows[np.linalg.norm(B[rows] - A[rows], axis=1) > 0]     # ends apart: sides defined
    now = sides(view, X[rows], A[rows], B[rows], nA[rows], nB[rows])
    had = rows[has_sides[rows]]
    j = np.flatnonzero(has_sides[rows])
    a, b, r = flips(tuple(x[had] for x in before), tuple(x[j] for x in now), OFFSET * base[had])
    return a, b, had[r], rows, now
