"""Stacks: structurally identical subtrees of one union or blend, evaluated as one.

A train has 26 wheels, each the difference of a disc and six holes; evaluated one
subtree at a time, a batch of points costs some 20 small numpy calls per wheel whatever
its size. A :class:`Stack` holds K such members (operator subtrees of Groups and Ops with
the same shape: kinds, member counts, reductions, operators) with the parameters of
each position packed over all members. Evaluation forms (point, member) pairs from the
members' support boxes and runs the shared shape once on all pairs, then reduces the
pairs of each point as the parent does (sum for a blend, max for a union, where a
member whose box misses the point counts as 0). The kernels and combinations are the
ones every other plan node uses (see evaluate.py), so values equal the unstacked
evaluation.
"""
import numpy as np

from . import primitives as PR
from . import groups as G
from .groups import Group
from .plan_nodes import Op

STACK_MIN = 3                 # fewer identical subtrees are left as they are
PAIR_BLOCK = 1 << 22          # booleans per block of the (point, member) box test
# stacks of GRID_MIN_MEMBERS or more look their boxes up in a grid for batches of at least
# GRID_MIN_PAIRS (point, member) tests (the train's 26 wheels: 5000 cost the same either
# way, 40000 3.5x less)
GRID_MIN_MEMBERS = 8
GRID_MIN_PAIRS = 1 << 13
GRID_MAX_DIM = 64             # cells of that grid along an axis, at most
# subtrees that would evaluate more primitives than this on each point keep their own
# spatial pruning (a stack evaluates every position of a member on each of its points:
# every primitive of a small group, the nearby ones of a gridded group)
STACK_MAX_PRIMS = 16


def signature(node):
    """A hashable description of a plan node's shape, or None when it cannot be stacked
    (warps, and bare groups, which the plan already pools by kind)."""
    if "_signature" in node.__dict__:          # kept on the plan node: each subtree once
        return node._signature
    sig = None
    if isinstance(node, Group):
        sig = ("group", node.kind, node.m, node.reduce, node.n)
    elif isinstance(node, Op):
        kids = tuple(signature(c) for c in node.children)
        if all(k is not None for k in kids):
            sig = ("op", node.op, node.iso, node.n, kids)
    node._signature = sig
    return sig


def _prims(sig):
    """The primitives a member of this shape evaluates on each point, counting a gridded
    group (which meets only the few near a point) as one."""
    if sig[0] == "group":
        return 1 if sig[2] >= G.GRID_MIN_MEMBERS else sig[2]
    return sum(_prims(k) for k in sig[4])


class StackedGroup:
    """The groups at one position of every member: K * m primitives, member k's at
    rows k*m .. k*m + m - 1. Groups of GRID_MIN_MEMBERS or more get one candidate grid
    over all K * m primitives (built on first use), as a plain group has over its own."""

    def __init__(self, groups):
        self.m = groups[0].m
        self.reduce, self.n = groups[0].reduce, groups[0].n
        self.prm = PR.pack([p for g in groups for p in g.sources])
        self._gridded = self.m >= G.GRID_MIN_MEMBERS
        self._grid = None

    @property
    def grid(self):
        if self._gridded and self._grid is None:
            self._grid = G._build_grid(self.prm, *PR.support_bounds(self.prm))
        return self._grid

    def dense(self, v):
        """Whether v pair points pair with every primitive of their member (no grid)."""
        return self.grid is None or v * self.m <= G.SMALL_DENSE

    def pairs(self, P, kk):
        """(pair, primitive) pairs for pair points P (3, v), pair j standing for member
        kk[j]: the member's primitives, sorted by pair and then by primitive (global
        rows); with a grid, only those whose support can reach the point. Returns the
        pair index and primitive row of each, and the count of each pair's."""
        v = P.shape[1]
        if self.dense(v):
            pp, pi = np.divmod(np.arange(v * self.m), self.m)
            return pp, kk.take(pp) * self.m + pi, np.full(v, self.m)
        pp, pi, _ = G.grid_pairs(self.grid, P)
        mine = pi // self.m == kk[pp]               # other members' primitives in the cell
        pp, pi = pp[mine], pi[mine]
        return pp, pi, np.bincount(pp, minlength=v)


class StackedOp:
    def __init__(self, ops):
        first = ops[0]
        self.op, self.iso, self.n = first.op, first.iso, first.n
        self.children = [template([o.children[i] for o in ops]) for i in range(len(first.children))]


def template(nodes):
    return StackedGroup(nodes) if isinstance(nodes[0], Group) else StackedOp(nodes)


class Stack:
    """K members of one n-ary parent; ``reduce`` is the parent's: "sum" or "max"."""

    def __init__(self, members, reduce):
        self.K = len(members)
        self.reduce = reduce
        self.shape = template(members)
        self.member_lo = np.array([m.lo for m in members], float)
        self.member_hi = np.array([m.hi for m in members], float)
        self.lo, self.hi = self.member_lo.min(0), self.member_hi.max(0)
        vl = [m.vlo for m in members]
        vh = [m.vhi for m in members]
        if reduce == "sum":
            self.vlo, self.vhi = float(sum(vl)), float(sum(vh))
        else:
            self.vlo, self.vhi = float(max(vl)), float(max(vh))
        self.grid = _member_grid(self.lo, self.hi, self.member_lo, self.member_hi) \
            if self.K >= GRID_MIN_MEMBERS else None

    def __repr__(self):
        return f"Stack({self.K} x {self.shape.op}, {self.reduce})"

    def pairs(self, P):
        """(point, member) pairs whose member box holds the point, sorted by point and
        then by member. A large batch of a stack of many members tests only the
        members whose boxes meet the point's grid cell (:func:`_member_grid`); the
        others test every box, in blocks of points, so that a stack of thousands of
        members never needs more than PAIR_BLOCK booleans at a time."""
        n = P.shape[1]
        if self.grid is not None and n * self.K >= GRID_MIN_PAIRS:
            return self._grid_pairs(P)
        step = max(1, PAIR_BLOCK // (3 * self.K))
        pp, kk = [], []
        for a in range(0, n, step):
            X = P[:, a:a + step].T[:, None, :]                   # (points, 1, 3) against (K, 3) boxes
            i, j = np.nonzero(((X >= self.member_lo) & (X <= self.member_hi)).all(axis=2))
            pp.append(i + a)
            kk.append(j)
        if len(pp) == 1:
            return pp[0], kk[0]
        return (np.concatenate(pp), np.concatenate(kk)) if pp else (np.zeros(0, np.int64),) * 2

    def _grid_pairs(self, P):
        g = self.grid
        n = P.shape[1]
        flat = np.zeros(n, np.int64)
        for k in range(3):
            c = np.clip(np.floor((P[k] - g["lo"][k]) * g["inv"][k]), 0, g["dims"][k] - 1).astype(np.int64)
            flat += c * g["stride"][k]
        pp, kk, _ = G.cell_lists(g["offsets"], g["items"], flat)
        inside = np.ones(len(pp), bool)
        for k in range(3):
            x = P[k].take(pp)
            inside &= (x >= self.member_lo[kk, k]) & (x <= self.member_hi[kk, k])
        return pp[inside], kk[inside]


def _member_grid(lo, hi, member_lo, member_hi):
    """A uniform grid over a stack's box, cells about a member box's median size (at
    most GRID_MAX_DIM along an axis), listing in each cell the members whose boxes
    meet it, in member order (CSR: offsets, items). A point's cell is found by the
    same monotone floor as a box's corners (clamped into the grid), so every member
    whose box holds the point is in its cell's list."""
    ext = np.maximum(hi - lo, 0.0)
    size = np.median(member_hi - member_lo, axis=0)
    dims = np.ones(3, np.int64)
    wide = ext > 0
    dims[wide] = np.clip(np.ceil(ext[wide] / np.maximum(size[wide], ext[wide] / GRID_MAX_DIM)), 1, GRID_MAX_DIM)
    inv = np.where(wide, dims / np.where(wide, ext, 1.0), 0.0)
    a = np.clip(np.floor((member_lo - lo) * inv), 0, dims - 1).astype(np.int64)
    b = np.clip(np.floor((member_hi - lo) * inv), 0, dims - 1).astype(np.int64)
    stride = np.array([dims[1] * dims[2], dims[2], 1], np.int64)
    cells, owners = [], []
    for k in range(len(a)):
        i, j, m = np.meshgrid(*(np.arange(a[k, d], b[k, d] + 1) for d in range(3)), indexing="ij")
        cells.append((i * stride[0] + j * stride[1] + m).ravel())
        owners.append(np.full(cells[-1].size, k, np.int64))
    cells, owners = np.concatenate(cells), np.concatenate(owners)
    order = np.lexsort((owners, cells))
    total = int(np.prod(dims))
    offsets = np.zeros(total + 1, np.int64)
    offsets[1:] = np.cumsum(np.bincount(cells, minlength=total))
    return {"lo": lo.astype(float), "inv": inv, "dims": dims, "stride": stride,
            "offsets": offsets, "items": owners[order]}


def stack_children(kids, reduce):
    """The children of a union ("max") or blend ("sum") with every set of at least
    STACK_MIN identical shapes replaced by one Stack (at the place of its first)."""
    by_sig = {}
    for i, k in enumerate(kids):
        sig = signature(k)
        if sig is not None and sig[0] == "op" and _prims(sig) <= STACK_MAX_PRIMS:
            by_sig.setdefault(sig, []).append(i)
    sets = [ix for ix in by_sig.values() if len(ix) >= STACK_MIN]
    if not sets:
        return kids
    first = {ix[0]: ix for ix in sets}
    gone = {i for ix in sets for i in ix[1:]}
    out = []
    for i, k in enumerate(kids):
        if i in first:
            out.append(Stack([kids[j] for j in first[i]], reduce))
        elif i not in gone:
            out.append(k)
    return out
