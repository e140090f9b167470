"""Silhouettes that start on creases: a crease trace compares each step with the
previous one (identify feature points, MASSRIS section 6) and seeds a silhouette where
a sheet's normal turns from facing the eye to facing away. Where overlapping parts meet
(a locomotive's wheels) such silhouette arcs end at creases at both ends, and the rough
polygonisation's edges may cross none of them."""
import numpy as np

from ..blackboard.board import KIND_ID
from .surface import unit

OFFSET = 0.15       # seeds lie this many steps into their sheet (a silhouette meeting the
                    # crease obliquely still crosses the seed bracket); the two sheets'
                    # seeds are told apart by their normals (TracedPoints.near)


def sides(view, X, A, B, nA, nB):
    """(point, side directions, side facings) of crease points X from their bracket
    ends A, B and the two sheets' normals there, vectorised."""
    W = unit(B - A)                                   # from side A towards side B
    facing = np.stack([np.einsum("ij,ij->i", nA, view.towards_eye(A)),
                       np.einsum("ij,ij->i", nB, view.towards_eye(B))], axis=1)
    return [(X[i], (-W[i], W[i]), facing[i]) for i in range(len(X))]


def flips(before, now, d):
    """Seed brackets for silhouettes leaving a crease between two of its points: the
    sheets are matched by their side directions, and where a sheet's facing changed sign
    the bracket runs d into that sheet at both points."""
    x0, dirs0, facing0 = before
    x1, dirs1, facing1 = now
    same = dirs0[0] @ dirs1[0] >= 0
    out = []
    for side in (0, 1):
        old = side if same else 1 - side
        if (facing0[old] > 0) != (facing1[side] > 0):
            out.append((x0 + d * dirs0[old], x1 + d * dirs1[side]))
    return out


def seed_sides(session, X, A, B):
    """The side records of new crease seeds (their sheets' normals from one batched
    evaluation at the bracket ends)."""
    if len(X) == 0:
        return []
    _, g = session.ev.field_grad(np.concatenate([A, B]))
    n = session.surface.normals(g)
    return sides(session.view, X, A, B, n[:len(X)], n[len(X):])


def silhouettes_off_creases(session, trs, X, A, B, nA, nB, ok):
    """After a trace step: the seed brackets (a, b, cell) of silhouettes that start on the
    creases between each crease trace's last and current point; updates the traces'
    side records."""
    if "silhouette" not in session.settings.kinds:
        return []
    rows = np.array([i for i, tr in enumerate(trs) if tr.kind == KIND_ID["crease"] and ok[i]], np.int64)
    rows = rows[np.linalg.norm(B[rows] - A[rows], axis=1) > 0]     # ends apart: sides defined
    if len(rows) == 0:
        return []
    now = sides(session.view, X[rows], A[rows], B[rows], nA[rows], nB[rows])
    seeds = []
    for i, rec in zip(rows, now):
        tr = trs[i]
        if tr.sides is not None:
            cell = tr.base / session.settings.step          # the trace's scale: its seeds'
            seeds += [(x, y, cell) for x, y in flips(tr.sides, rec, OFFSET * tr.base)]
        tr.sides = rec
    return seeds
