"""Silhouettes that start on creases: a crease trace compares each step with the
previous one (identify feature points, MASSRIS section 6) and seeds a silhouette where
a sheet's normal turns from facing the eye to facing away."""
import numpy as np

from ..blackboard.board import KIND_ID


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


def silhouettes_off_creases(session, trs, X, A, B, nA, nB, ok):
    """Identify feature points along creases (current step against the previous
    one): where a sheet's normal at the crease turns from facing the eye to facing
    away, a silhouette of that sheet starts at the crease. Where overlapping parts
    meet (a locomotive's wheels) such silhouette arcs end at creases at both ends,
    and the rough polygonisation's edges may cross none of them. Returns seed
    brackets (a, b) 0.6 of a step into the sheet at the previous and the current crease
    point (the two sheets' seeds, 1.2 steps apart, are not taken for one outline)."""
    if "silhouette" not in session.settings.kinds:
        return []
    seeds = []
    crease = KIND_ID["crease"]
    for i, tr in enumerate(trs):
        if tr.kind != crease or not ok[i]:
            continue
        W = B[i] - A[i]
        L = np.linalg.norm(W)
        if not L > 0:
            continue
        W = W / L                             # from side A towards side B
        facing = np.array([nA[i] @ session.view.towards_eye(A[i:i + 1])[0],
                           nB[i] @ session.view.towards_eye(B[i:i + 1])[0]])
        now = (X[i], (-W, W), facing)
        if tr.sides is not None:
            seeds += flips(tr.sides, now, 0.6 * session.step_len)
        tr.sides = now
    return seeds


def crease_sides(session, X, A, B):
    """(point, side directions, side facings) of crease points from their bracket
    ends (one batched evaluation)."""
    if len(X) == 0:
        return []
    _, g = session.ev.field_grad(np.concatenate([A, B]))
    n = session.surface.normals(g)
    facing = np.einsum("ij,ij->i", n, session.view.towards_eye(np.concatenate([A, B]))).reshape(2, -1)
    W = B - A
    W /= np.maximum(np.linalg.norm(W, axis=1, keepdims=True), 1e-300)
    return [(X[i], (-W[i], W[i]), facing[:, i]) for i in range(len(X))]
