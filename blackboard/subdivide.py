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

from .polygonise import edge_ends, refine_crossings

# the fine-cell edges of cell (i, j, l), per axis: offsets of their lower corners
_CELL_EDGES = [(a, d1, d2) for a in range(3) for d1 in (0, 1) for d2 in (0, 1)]
_PAIRS = np.array([(i, j) for i in range(12) for j in range(i + 1, 12)])
MAX_CORNERS = 4_000_000        # fine corners evaluated in one call (memory stays bounded)


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
    # every sign-changing fine edge, refined in one batch
    ends, starts = [], []
    for a in range(3):
        s0, s1 = edge_ends(a)
        s0, s1 = (slice(None),) + s0, (slice(None),) + s1
        change = inside[s0] != inside[s1]
        starts.append((a, np.argwhere(change)))             # (voxel, i, j, l) of the lower corner
        ends.append((P[s0][change], P[s1][change], F[s0][change], F[s1][change]))
    A, B, fA, fB = (np.concatenate([e[i] for e in ends]) for i in range(4))
    empty = _none(kinds)
    if len(A) == 0:
        return empty
    X = refine_crossings(ev, A, B, fA, fB)
    _, g = ev.field_grad(X)
    gn = np.linalg.norm(g, axis=1, keepdims=True)
    N = np.where(gn > 0, -g / np.maximum(gn, 1e-300), np.nan)          # outward normals
    # crossings by edge, NaN where an edge has none: (axis, m, k+1, k+1, k+1, 3)
    XE = np.full((3, m, k + 1, k + 1, k + 1, 3), np.nan)
    NE = np.full((3, m, k + 1, k + 1, k + 1, 3), np.nan)
    at = 0
    for a, idx in starts:
        sel = (a, *idx.T)
        XE[sel], NE[sel] = X[at:at + len(idx)], N[at:at + len(idx)]
        at += len(idx)
    # the twelve edges of each fine cell: (m, k, k, k, 12, 3)
    cx, cn = [], []
    for a, d1, d2 in _CELL_EDGES:
        sl = [slice(None)] * 4
        b, c = (a + 1) % 3, (a + 2) % 3
        sl[1 + a] = slice(0, k)
        sl[1 + b] = slice(d1, d1 + k)
        sl[1 + c] = slice(d2, d2 + k)
        cx.append(XE[a][tuple(sl)])
        cn.append(NE[a][tuple(sl)])
    CX, CN = np.stack(cx, axis=-2).reshape(-1, 12, 3), np.stack(cn, axis=-2).reshape(-1, 12, 3)
    valid = np.all(np.isfinite(CN), axis=2) & np.all(np.isfinite(CX), axis=2)
    cells = np.flatnonzero(valid.sum(axis=1) >= 2)
    if len(cells) == 0:
        return empty
    CX, CN, valid = CX[cells], CN[cells], valid[cells]
    a, b = _PAIRS[:, 0], _PAIRS[:, 1]
    both = valid[:, a] & valid[:, b]
    XA, XB = CX[:, a], CX[:, b]                                       # (c, 66, 3)
    dist = np.linalg.norm(XA - XB, axis=2)
    out = {}
    for kind in kinds:
        if kind == "silhouette":
            s = np.einsum("cek,cek->ce", np.nan_to_num(CN), view.towards_eye(np.nan_to_num(CX).reshape(-1, 3))
                          .reshape(CX.shape))
            pair = (s[:, a] > 0) != (s[:, b] > 0)
        elif kind == "crease":
            dot = np.einsum("cpk,cpk->cp", np.nan_to_num(CN[:, a]), np.nan_to_num(CN[:, b]))
            pair = np.arccos(np.clip(dot, -1, 1)) > crease_angle
        else:
            continue
        score = np.where(both & pair, dist, np.inf)
        best = score.argmin(axis=1)
        c = np.flatnonzero(np.isfinite(score[np.arange(len(score)), best]))
        pa, pb = XA[c, best[c]], XB[c, best[c]]
        mid = 0.5 * (pa + pb)
        # one feature point per kind in each block of 2^3 fine cells: neighbouring fine
        # cells on one outline would each start a trace of it
        _, first = np.unique(np.floor((mid - lo) / (2 * h / k)).astype(np.int64), axis=0, return_index=True)
        first = np.sort(first)
        out[kind] = (mid[first], pa[first], pb[first])
    for kind in kinds:
        out.setdefault(kind, empty[kind])
    return out
