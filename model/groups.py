"""Groups of primitives of one kind evaluated together on (point, primitive) pairs.

A group belongs to an n-ary operator whose reduction it performs: ``sum`` (blend),
``max`` (union of non-negative primitives) or ``ricci`` ((sum f^n)^(1/n)). Candidate
pairs come from a uniform grid whose cells list the primitives whose support can reach
them (a cell-to-skeleton-box distance test against each radius), so a point meets only
the few primitives near it: one vectorised kernel call per group instead of one
Python-level call per primitive.
"""
import numpy as np

from . import primitives as PR
from .branches import ZERO, forced, pair_choice

GRID_MIN_MEMBERS = 5         # smaller groups test every member on every point
GRID_MAX_CELLS = 48 ** 3
SMALL_DENSE = 2048           # a small batch tests every member: cheaper than the grid lookup
PAIR_BLOCK = 1 << 21         # (primitive, cell) pairs tested at once when the grid is built


class Group:
    def __init__(self, prims, reduce="sum", n=1.0, use_grid=True):
        self.prm = PR.pack(prims)
        self.sources = tuple(prims)          # lets plans merge groups
        self.kind = self.prm["kind"]
        self.m = len(prims)
        self.reduce = reduce
        self.n = float(n)
        plo, phi = PR.support_bounds(self.prm)
        self.member_lo, self.member_hi = plo, phi
        self.lo, self.hi = plo.min(0), phi.max(0)
        S = self.prm["S"]
        if reduce == "sum":
            self.vlo, self.vhi = float(np.minimum(S, 0).sum()), float(np.maximum(S, 0).sum())
        elif reduce == "max":
            self.vlo, self.vhi = 0.0, float(S.max())
        else:
            self.vlo, self.vhi = 0.0, float((np.maximum(S, 0) ** self.n).sum() ** (1 / self.n))
        self._gridded = use_grid and self.m >= GRID_MIN_MEMBERS
        self._grid = None

    def __repr__(self):
        return f"Group({self.kind} x{self.m}, {self.reduce})"

    @property
    def grid(self):
        """The candidate grid, built on first use: compiling a plan makes groups that a
        parent group absorbs (nested blends), which never evaluate."""
        if self._gridded and self._grid is None:
            self._grid = _build_grid(self.prm, self.member_lo, self.member_hi)
        return self._grid

    def dense(self, n):
        """Whether a batch of n points pairs with every member (no grid lookup)."""
        return self.grid is None or n * self.m <= SMALL_DENSE

    def pairs(self, P):
        """Candidate pairs for P (3, n): point index and member index of each pair,
        sorted by point, and the number of pairs of each point."""
        n = P.shape[1]
        if self.dense(n):
            if self.m == 1:
                return None, None, None
            pp, pi = np.divmod(np.arange(n * self.m), self.m)      # every member, point by point
            return pp, pi, np.full(n, self.m)
        return grid_pairs(self.grid, P)

    def evaluate(self, P, need_grad, stats=None, ctx=None):
        pp, pi, counts = self.pairs(P)
        # pairs beyond a primitive's radius just give 0 (no compaction pass); columns
        # are gathered with take (indexing P[:, pp] is several times slower)
        Q = P if pi is None else P.take(pp, axis=1)
        dense = self.m if pi is not None and self.dense(P.shape[1]) else None
        return evaluate_pairs(self.prm, self.reduce, self.n, Q, pi, pp, P.shape[1], need_grad, stats, ctx, self,
                              dense)


def grid_pairs(g, P):
    """Candidate pairs of P (3, n) from a grid (:func:`_build_grid`): point index and
    primitive index of each pair, sorted by point and, within a point, by primitive
    (the order of every member on every point, less the ones too far to count), and
    the number of pairs of each point."""
    n = P.shape[1]
    lo, inv, dims = g["lo"], g["inv_cs"], g["dims"]
    ok = np.ones(n, bool)
    flat = np.zeros(n, np.int64)
    for k in range(3):
        c = np.floor((P[k] - lo[k]) * inv).astype(np.int64)
        ok &= (c >= 0) & (c < dims[k])
        flat += c * g["stride"][k]
    flat[~ok] = g["empty"]
    return cell_lists(g["offsets"], g["items"], flat)


def cell_lists(offsets, items, flat):
    """Every point's cell list of a CSR grid (cell c lists items[offsets[c]:offsets[c+1]]),
    point i in cell flat[i]: the point index and item of each pair, sorted by point and
    in list order within a point, and the number of pairs of each point."""
    start = offsets[flat]
    counts = offsets[flat + 1] - start
    pp = np.repeat(np.arange(len(flat)), counts)
    # position of each pair inside its cell's list
    local = np.arange(len(pp)) - np.repeat(np.cumsum(counts) - counts - start, counts)
    return pp, items[local], counts


def evaluate_pairs(prm, reduce, n_exp, Q, idx, pp, n, need_grad, stats=None, ctx=None, node=None, dense=None):
    """The kernels of (point, member) pairs reduced per point: Q (3, pairs) holds each
    pair's point, idx its member (None: the group's only member), pp its point among n
    (sorted; None: one pair per point, nothing to reduce). ``ctx``: a branch record or
    pins (model.branches) for a union's choice of member, at site ``node``. ``dense``
    (a count m): the pairs are every point's m members in order, n * m of them (a max
    then reduces rows of an (n, m) array)."""
    if stats is not None:
        stats.pairs += Q.shape[1]
    d2, V = PR.dist2(Q, prm, idx)
    f, g = PR.kernel(d2, V, prm, idx, need_grad)
    if pp is None:
        return _single(f, g, reduce)
    if ctx is not None and reduce == "max":
        w = np.full(n, ZERO, np.int64)
        if len(pp):
            owners, seg_max, win = segment_max(pp, f, dense=dense)
            w[owners] = np.where(seg_max > 0, idx[win], ZERO)
        pinned = forced(ctx, node, w)
        if pinned is not None:
            return pair_choice(n, pp, idx, f, g, pinned)
    return _reduce(reduce, n_exp, n, pp, f, g, dense)


def _single(f, g, reduce):
    if reduce == "ricci":
        # (f^n)^(1/n) of non-negative f is f itself
        return np.maximum(f, 0.0), (None if g is None else np.where(f > 0, g, 0.0))
    return f, g


def _bincount(pp, w, n):
    # np.bincount returns int64 for empty input even with float weights
    return np.bincount(pp, weights=w, minlength=n).astype(np.float64, copy=False)


def segment_max(pp, f, winners=True, dense=None):
    """Per point of pairs sorted by point (pp, non-empty): the point, the largest f of
    its pairs and (``winners``) the first pair that attains it, as argmax would.
    ``dense`` (m): every point has m pairs (rows of an (n, m) array)."""
    if dense is not None:
        rows = f.reshape(-1, dense)
        j = rows.argmax(axis=1)
        first = np.arange(0, len(f), dense)
        return pp.take(first), rows[np.arange(len(rows)), j], (first + j if winners else None)
    change = np.empty(len(pp), bool)
    change[0] = True
    np.not_equal(pp[1:], pp[:-1], out=change[1:])
    starts = np.flatnonzero(change)
    seg_max = np.maximum.reduceat(f, starts)
    win = None
    if winners:
        seg_id = np.cumsum(change) - 1
        hit = np.flatnonzero(f == seg_max[seg_id])
        sh = seg_id[hit]                      # hits are in pair order: keep each segment's first
        first = np.ones(len(hit), bool)
        np.not_equal(sh[1:], sh[:-1], out=first[1:])
        win = hit[first]
    return pp[starts], seg_max, win


def _reduce(reduce, n_exp, n, pp, f, g, dense=None):
    if reduce == "sum":
        F = _bincount(pp, f, n)
        if g is None:
            return F, None
        return F, np.stack([_bincount(pp, g[k], n) for k in range(3)])
    if reduce == "max":
        F = np.zeros(n)
        G = np.zeros((3, n)) if g is not None else None
        if len(pp) == 0:
            return F, G
        owners, seg_max, win = segment_max(pp, f, g is not None, dense)
        F[owners] = np.maximum(seg_max, 0.0)
        if g is not None:
            G[:, owners] = np.where(f[win] > 0, g.take(win, axis=1), 0.0)
        return F, G
    # ricci over non-negative members
    fp = np.maximum(f, 0.0)
    S = _bincount(pp, fp ** n_exp, n)
    F = S ** (1.0 / n_exp)
    if g is None:
        return F, None
    w = fp ** (n_exp - 1.0)
    W = np.stack([_bincount(pp, w * g[k], n) for k in range(3)])
    with np.errstate(divide="ignore", invalid="ignore"):
        c = np.where(F > 0, F ** (1.0 - n_exp), 0.0)
    return F, c * W


def _build_grid(prm, plo, phi):
    lo = plo.min(0)
    hi = phi.max(0)
    ext = np.maximum(hi - lo, 1e-12)
    typical = np.median(phi - plo, axis=0).max()
    cs = max(typical / 2.0, (np.prod(ext) / GRID_MAX_CELLS) ** (1 / 3), 1e-12)
    dims = np.maximum(np.ceil(ext / cs).astype(np.int64), 1)
    slo, shi = PR.skeleton_bounds(prm)
    R = prm["R"]
    a = np.clip(np.floor((plo - lo) / cs).astype(np.int64), 0, dims - 1)       # (m, 3) cell ranges
    b = np.clip(np.floor((phi - lo) / cs).astype(np.int64), 0, dims - 1)
    span = b - a + 1
    count = np.prod(span, axis=1)
    cells_of = []
    members = []
    # every (primitive, cell of its box) pair, vectorised over primitives in blocks
    # of about PAIR_BLOCK pairs
    ends = np.cumsum(count)
    i0 = 0
    while i0 < len(R):
        i1 = max(int(np.searchsorted(ends, ends[i0] - count[i0] + PAIR_BLOCK, side="right")), i0 + 1)
        sel = np.arange(i0, i1)
        n = count[sel]
        prim = np.repeat(sel, n)
        k = np.arange(int(n.sum())) - np.repeat(np.cumsum(n) - n, n)
        sy, sz = span[prim, 1], span[prim, 2]
        cidx = a[prim] + np.stack([k // (sy * sz), (k // sz) % sy, k % sz], axis=1)
        clo = lo + cidx * cs
        chi = clo + cs
        # distance between the cell box and the skeleton's box
        gap = np.maximum(np.maximum(slo[prim] - chi, clo - shi[prim]), 0.0)
        near = np.einsum("ij,ij->i", gap, gap) < R[prim] * R[prim]
        c = cidx[near]
        cells_of.append(c[:, 0] * dims[1] * dims[2] + c[:, 1] * dims[2] + c[:, 2])
        members.append(prim[near])
        i0 = i1
    cells = np.concatenate(cells_of) if cells_of else np.zeros(0, np.int64)
    mem = np.concatenate(members) if members else np.zeros(0, np.int64)
    order = np.argsort(cells, kind="stable")
    ncell = int(np.prod(dims))
    counts = np.bincount(cells, minlength=ncell + 1)   # the extra last cell stays empty
    offsets = np.concatenate([[0], np.cumsum(counts)])
    return {"lo": lo, "inv_cs": 1.0 / cs, "cs": cs, "dims": dims,
            "stride": np.array([dims[1] * dims[2], dims[2], 1]),
            "empty": ncell, "offsets": offsets, "items": mem[order]}
