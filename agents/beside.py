"""Silhouettes beside traced silhouettes: where the surface folds (a shell's sutures),
silhouettes run side by side, or beside a crease, closer than a polygon edge is long.
An edge across both sees n.v keep its sign and gives no seed. Once the edge seeds are
traced, agents step sideways from every third traced silhouette point, across its
outline and on the surface, up to a voxel each way; a second sign change of n.v on a
side is a new approximate feature point (paper section 6: identify feature points by
comparing each step with the previous one). A sign change where the normal jumps (a
crease) counts only where n.v is small on one side of it: a silhouette is near."""
import numpy as np

from ..blackboard.keys import unique_rows
from ..model.vectors import cross
from .steering import unit

OFFSETS = np.array([0.2, 0.4, 0.7, 1.0])               # sideways, in voxels
EVERY = 3                                              # every third traced point
NEAR_ZERO = 0.25                                       # |n.v| beside a crease's jump


def seeds_beside_silhouettes(outlines, surface, board, traced, step_len, crease_angle, region_ok=None):
    """Approximate silhouette points beside the traced silhouettes among ``outlines``,
    added to the blackboard (bracket: the two sideways samples either side of the sign
    change), one per half voxel; a bracket across an outline already among the
    ``traced`` points (agents.traced) is no news. Returns how many were added."""
    sil = [o for o in outlines if o.kind == "silhouette" and len(o.points) >= 2]
    if not sil:
        return 0
    P = np.concatenate([o.points[::EVERY] for o in sil])
    N = np.concatenate([o.normals[::EVERY] for o in sil])
    T = unit(np.concatenate([np.gradient(o.points, axis=0)[::EVERY] for o in sil]))
    if region_ok is not None:
        keep = region_ok(P)
        P, N, T = P[keep], N[keep], T[keep]
    if len(P) == 0:
        return 0
    W = unit(cross(N, T))
    h, k = board.h, len(OFFSETS)
    base = np.concatenate([P, P])
    side = np.concatenate([W, -W])
    S = base[:, None, :] + (OFFSETS * h)[None, :, None] * side[:, None, :]
    # a few Newton steps: only the sign of n.v is wanted (the seeds are refined later)
    Q, _, g = surface.project(S.reshape(-1, 3), steps=3, anchor=np.repeat(base, k, axis=0))
    n = surface.normals(g)
    nv = np.einsum("ij,ij->i", n, surface.view.towards_eye(Q)).reshape(-1, k)
    Q, n = Q.reshape(-1, k, 3), n.reshape(-1, k, 3)
    # the sign just beside the outline, then the first sample where it flips again
    flip = (nv[:, 1:] > 0) != (nv[:, :1] > 0)
    rows = np.flatnonzero(flip.any(axis=1))
    j = np.argmax(flip[rows], axis=1) + 1
    smooth = np.einsum("ij,ij->i", n[rows, j - 1], n[rows, j]) > np.cos(0.5 * crease_angle)
    small = np.minimum(np.abs(nv[rows, j - 1]), np.abs(nv[rows, j])) < NEAR_ZERO
    keep = smooth | small
    rows, j = rows[keep], j[keep]
    if len(rows) == 0:
        return 0
    a, b = Q[rows, j - 1], Q[rows, j]
    pos = 0.5 * (a + b)
    # a bracket across an outline already traced (the flip is that outline) is no news
    new = traced.unknown("silhouette", pos, 0.5 * step_len)
    a, b, pos = a[new], b[new], pos[new]
    _, first = unique_rows(np.floor(pos / (0.5 * h)).astype(np.int64), return_index=True)
    first = np.sort(first)
    if len(first):
        board.add_features(pos[first], a[first], b[first], "silhouette")
    return len(first)
