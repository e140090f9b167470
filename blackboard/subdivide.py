"""Voxel subdivision (MASSRIS section 9: polygons recalculated in subdivided voxels, for
"a better approximation to the surface locally" and the parts "missed due to the low
resolution polygonal sampling").

Chosen voxels of the blackboard are resampled on a k^3 grid each (one batched field
evaluation for all of them). Every sign-changing fine grid edge is a surface point
(regula falsi along the edge, as the rough polygonisation's crossings), with its
normal from one batched gradient evaluation. The crossings on the twelve edges of a
fine cell are the cell's samples of the surface; of the pairs of them that cross a
feature outline (n.v changes sign: a silhouette; normals apart by more than the crease
angle: a crease), the closest pair becomes an approximate feature point with that pair
as its bracket, as a polygon edge's crossing does (section 4). Features smaller than a
rough cell (a wheel's holes) are found this way at the fine cells' scale: the feature
points remember that scale (their agents trace with steps of it).
"""
import numpy as np

from ..model.tolerances import CROSSING, field_tol
from .keys import unique_rows
from .polygonise import edge_ends, refine_crossings

# the fine-cell edges of cell (i, j, l), per axis: offsets of their lower corners
_CELL_EDGES = [(a, d1, d2) for a in range(3) for d1 in (0, 1) for d2 in (0, 1)]
_PAIRS_OF = {k: np.array([(i, j) for i in range(k) for j in range(i + 1, k)]) for k in (4, 6, 12)}
MAX_CORNERS = 4_000_000        # fine corners evaluated in one call (memory stays bounded)


def _closest_pairs(E, valid, X, accept):
    """In each cell (a row of E: its twelve edges' crossing numbers, ``valid`` where
    usable), the closest pair of valid crossings that ``accept(ia, ib)`` takes (arrays of
    crossing numbers, (cells, pairs) -> bool); returns the pairs' points (a, b), in cell
    order, a on the edge that comes first, for the cells that have one. A cell's valid
    crossings are moved to the front first (in edge order: the pairs keep their order),
    and cells with at most four of them (most) try their six pairs, with five or six (a
    plane cuts a cell in at most six edges) their 15, not all 66."""
    count = valid.sum(axis=1)
    front = np.take_along_axis(E, np.argsort(~valid, axis=1, kind="stable"), axis=1)
    rows_out, a_out, b_out = [], [], []
    for lo, hi in ((1, 4), (4, 6), (6, 12)):
        rows = np.flatnonzero((count > lo) & (count <= hi))
        if len(rows) == 0:
            continue
        pairs = _PAIRS_OF[hi]
        ia, ib = front[rows][:, pairs[:, 0]], front[rows][:, pairs[:, 1]]
        use = pairs[None, :, 1] < count[rows, None]
        XA, XB = X[ia], X[ib]
        D = XA - XB
        score = np.where(use & accept(ia, ib), D[..., 0] ** 2 + D[..., 1] ** 2 + D[..., 2] ** 2, np.inf)
        best = score.argmin(axis=1)
        c = np.flatnonzero(np.isfinite(score[np.arange(len(rows)), best]))
        rows_out.append(rows[c])
        a_out.append(XA[c, best[c]])
        b_out.append(XB[c, best[c]])
    if not rows_out:
        return np.zeros((0, 3)), np.zeros((0, 3))
    order = np.argsort(np.concatenate(rows_out), kind="stable")
    return np.concatenate(a_out)[order], np.concatenate(b_out)[order]


def fine_grid_points(lo, h, ijk, k):
    """Corners of the k^3 fine grid of each voxel: (m, k+1, k+1, k+1, 3)."""
    g = np.arange(k + 1) * (h / k)
    G = np.stack(np.meshgrid(g, g, g, indexing="ij"), axis=-1)
    return (lo + np.asarray(ijk) * h)[:, None, None, None, :] + G[None]


def fine_features(ev, lo, h, ijk, k, view, crease_angle, kinds=("silhouette", "crease")):
    """{kind: (points, a, b)} approximate feature points found in the voxels ``ijk``
    ((m, 3) integer triples of a grid of cell h with its corner (0, 0, 0) at lo),
    each voxel subdivided into k^3 cells: at most one per kind in each block of 2^3
    fine cells."""
    ijk = np.asarray(ijk, np.int64).reshape(-1, 3)
    out = _none(kinds)
    per = (k + 1) ** 3
    step = max(1, MAX_CORNERS // per)
    for s in range(0, len(ijk), step):
        part = _fine_block(ev, lo, h, ijk[s:s + step], k, view, crease_angle, kinds)
        out = {kind: tuple(np.concatenate([x, y]) for x, y in zip(out[kind], part[kind])) for kind in kinds}
    return out


def _none(kinds):
    return {kind: (np.zeros((0, 3)), np.zeros((0, 3)), np.zeros((0, 3))) for kind in kinds}


def _fine_block(ev, lo, h, ijk, k, view, crease_angle, kinds):
    m = len(ijk)
    P = fine_grid_points(lo, h, ijk, k)
    F = ev.field(P.reshape(-1, 3)).reshape(m, k + 1, k + 1, k + 1)
    inside = F >= ev.iso
    # every sign-changing fine edge, refined in one batch; ID numbers them by axis and
    # lower corner (-1: no crossing on that edge)
    ID = np.full((3, m, k + 1, k + 1, k + 1), -1, np.int64)
    ends, n = [], 0
    for a in range(3):
        s0, s1 = edge_ends(a)
        s0, s1 = (slice(None),) + s0, (slice(None),) + s1
        change = inside[s0] != inside[s1]
        idx = np.nonzero(change)
        ID[a][s0][change] = np.arange(n, n + len(idx[0]))
        n += len(idx[0])
        ends.append((P[s0][change], P[s1][change], F[s0][change], F[s1][change]))
    empty = _none(kinds)
    if n == 0:
        return empty
    A, B, fA, fB = (np.concatenate([e[i] for e in ends]) for i in range(4))
    # to |f - iso| <= CROSSING (the bracket ends a seed takes are projected onto the
    # surface again; from there in one Newton step): about a quarter fewer evaluations
    X = refine_crossings(ev, A, B, fA, fB, ftol=field_tol(ev.iso, CROSSING))
    _, g = ev.field_grad(X)
    gn = np.linalg.norm(g, axis=1, keepdims=True)
    N = -g / np.maximum(gn, 1e-300)                                   # outward normals
    good = (gn[:, 0] > 0) & np.all(np.isfinite(N), axis=1) & np.all(np.isfinite(X), axis=1)
    # the twelve edges of each fine cell: (cells, 12) crossing numbers
    cols = []
    for a, d1, d2 in _CELL_EDGES:
        sl = [slice(None)] * 4
        b, c = (a + 1) % 3, (a + 2) % 3
        sl[1 + a] = slice(0, k)
        sl[1 + b] = slice(d1, d1 + k)
        sl[1 + c] = slice(d2, d2 + k)
        cols.append(ID[a][tuple(sl)].reshape(-1))
    E = np.stack(cols, axis=1)
    valid = E >= 0
    valid[valid] = good[E[valid]]
    cells = np.flatnonzero(valid.sum(axis=1) >= 2)
    if len(cells) == 0:
        return empty
    E, valid = E[cells], valid[cells]
    E = np.where(valid, E, 0)
    out = {}
    for kind in kinds:
        if kind == "silhouette":
            s = np.einsum("ik,ik->i", N, view.towards_eye(X)) > 0
            S = s[E]
            # only cells whose valid crossings see both signs can hold such a pair
            cand = np.flatnonzero(np.any(valid & S, axis=1) & np.any(valid & ~S, axis=1))

            def accept(ia, ib):
                return s[ia] != s[ib]
        elif kind == "crease":
            # a pair apart by more than the angle needs a crossing more than half the
            # angle from the cell's first valid one (the triangle inequality on the sphere)
            ref = N[E[np.arange(len(E)), valid.argmax(axis=1)]]
            spread = np.einsum("cek,ck->ce", N[E], ref) < np.cos(0.5 * crease_angle)
            cand = np.flatnonzero(np.any(valid & spread, axis=1))

            cos_crease = np.cos(crease_angle)

            def accept(ia, ib):          # normals apart by more than the angle
                NA, NB = N[ia], N[ib]
                return NA[..., 0] * NB[..., 0] + NA[..., 1] * NB[..., 1] + NA[..., 2] * NB[..., 2] < cos_crease
        else:
            continue
        pa, pb = _closest_pairs(E[cand], valid[cand], X, accept)
        mid = 0.5 * (pa + pb)
        # one feature point per kind in each block of 2^3 fine cells: neighbouring fine
        # cells on one outline would each start a trace of it
        _, first = unique_rows(np.floor((mid - lo) / (2 * h / k)).astype(np.int64), return_index=True)
        first = np.sort(first)
        out[kind] = (mid[first], pa[first], pb[first])
    for kind in kinds:
        out.setdefault(kind, empty[kind])
    return out
