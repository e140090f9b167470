"""Field and gradient of a compiled plan on (N,3) float64 batches.

One evaluation path: a single point is a batch of one, and the naive reference (every
node on every point) runs the same functions on the unoptimised plan with pruning off.
With pruning on, every plan node first drops the points outside its support box, so a
subtree only ever sees the points that can feel it.
"""
import numpy as np

from . import branches as BR
from . import groups as G
from .groups import Group
from .plan import compile_plan
from .plan_nodes import Warp
from .sites import Sites
from .stack import Stack, StackedGroup

CHUNK = 1 << 16


class Stats:
    """Counters of the work an evaluation did (for benchmarks)."""

    def __init__(self):
        self.points = 0
        self.pairs = 0       # primitive kernel evaluations (point, primitive)

    @property
    def primitives_per_point(self):
        return self.pairs / max(self.points, 1)


def as_points(P):
    P = np.asarray(P, dtype=np.float64)
    if P.ndim == 1 and P.shape[0] == 3:
        P = P[None, :]
    if P.ndim != 2 or P.shape[1] != 3:
        raise ValueError(f"points must be an (N,3) array, got shape {P.shape}")
    return np.ascontiguousarray(P)


class Evaluator:
    """Evaluates a model: ``field(P)``, ``field_grad(P)`` (f and grad f)."""

    def __init__(self, model, optimize=True):
        self.model = model
        self.iso = model.iso
        self.plan = compile_plan(model, optimize=optimize)
        self.prune = optimize
        self.stats = Stats()
        self.memo = {}          # results that depend on the plan alone (e.g. the surface box)
        lo, hi = self.plan.lo, self.plan.hi
        self.bounds = (lo.copy(), hi.copy())
        finite = np.all(np.isfinite(lo)) and np.all(np.isfinite(hi)) and np.all(hi >= lo)
        self.scale = float(np.linalg.norm(hi - lo)) if finite else 1.0

    def field(self, P):
        return self._run(P, False)[0]

    def field_grad(self, P):
        return self._run(P, True)

    @property
    def sites(self):
        """The plan's decision sites (model.branches), numbered on first use."""
        if "sites" not in self.memo:
            self.memo["sites"] = Sites(self.plan)
        return self.memo["sites"]

    def record(self, P):
        """f, grad f and the branch record of each point: an (n, sites) int32 table
        of the child every max/min chose (model.branches)."""
        P = as_points(P)
        table = np.full((len(P), self.sites.count), BR.NOT_REACHED, np.int32)
        F, G = self.choose(P, table)
        return F, G, table

    def pinned(self, P, table):
        """f and grad f with each point's choices pinned to its row of a record
        (where the row reached a site; elsewhere as usual): the field of that row's
        sheet, continued smoothly across the creases around it."""
        P = as_points(P)
        table = np.asarray(table, np.int32)
        if table.shape != (len(P), self.sites.count):
            raise ValueError(f"pins must be an ({len(P)}, {self.sites.count}) table, got {table.shape}")
        return self._run(P, True, BR.Ctx(self.sites, table, None))

    def choose(self, P, table):
        """f and grad f with each point's row of ``table`` ((n, sites) int32) pinned
        where it has a choice, and every choice made written into it (in place): a row
        of NOT_REACHED comes out as the point's record, a pinned row as its pins with
        the choices at the other sites it reached. Records and pinned points in one
        evaluation (agents.asks)."""
        P = as_points(P)
        shape = (len(P), self.sites.count)
        if not (isinstance(table, np.ndarray) and table.dtype == np.int32 and table.shape == shape):
            raise ValueError(f"choices must be an ({len(P)}, {self.sites.count}) int32 array, got "
                             f"{getattr(table, 'shape', type(table).__name__)}")
        return self._run(P, True, BR.Ctx(self.sites, table, None, write=True))

    def _run(self, P, need_grad, ctx=None):
        P = as_points(P)
        n = len(P)
        self.stats.points += n
        F = np.empty(n)
        G = np.empty((n, 3)) if need_grad else None
        for a in range(0, n, CHUNK):
            cols = np.ascontiguousarray(P[a:a + CHUNK].T)      # (3, n) layout inside
            c = None if ctx is None else ctx.at(np.arange(a, a + cols.shape[1]))
            f, g = evaluate(self.plan, cols, need_grad, self.prune, self.stats, c)
            F[a:a + CHUNK] = f
            if need_grad:
                G[a:a + CHUNK] = g.T
        return F, G


def evaluate(node, P, need_grad, prune=True, stats=None, ctx=None):
    """Field (n,) and gradient (3, n) of a plan node at P (3, n), as dense arrays
    (``ctx``: a branch record or pins, model.branches)."""
    return _dense(_sparse(node, P, need_grad, prune, stats, None, ctx), P.shape[1], need_grad)


def _box(P):
    """The points' bounding box as two tuples of floats (cheap to compare in Python)."""
    return tuple(P.min(axis=1).tolist()), tuple(P.max(axis=1).tolist())


def _node_box(node):
    box = node.__dict__.get("_box_t")
    if box is None:
        box = node._box_t = (tuple(np.asarray(node.lo, float).tolist()), tuple(np.asarray(node.hi, float).tolist()))
    return box


def _sparse(node, P, need_grad, prune, stats, pbox, ctx=None):
    """(idx, f, g): the node's field and gradient at the columns idx of P (None: all
    columns); every other column lies outside the node's support, where it is 0."""
    n = P.shape[1]
    idx = None
    if prune and n:
        plo, phi = pbox if pbox is not None else _box(P)
        lo, hi = _node_box(node)
        if (phi[0] < lo[0] or phi[1] < lo[1] or phi[2] < lo[2] or
                plo[0] > hi[0] or plo[1] > hi[1] or plo[2] > hi[2]):
            return _EMPTY, _EMPTY_F, (_EMPTY_G if need_grad else None)
        cut = [k for k in range(3) if plo[k] < lo[k] or phi[k] > hi[k]]
        if cut:
            m = None
            for k in cut:                      # only the axes where some point is outside
                mk = (P[k] >= lo[k]) & (P[k] <= hi[k])
                m = mk if m is None else m & mk
            idx = np.flatnonzero(m)
            if len(idx) == 0:
                return _EMPTY, _EMPTY_F, (_EMPTY_G if need_grad else None)
            P = P.take(idx, axis=1)
            ctx = None if ctx is None else ctx.sub(idx)
    if isinstance(node, Group):
        f, g = node.evaluate(P, need_grad, stats, ctx)
    elif isinstance(node, Stack):
        sub, f, g = _stack(node, P, need_grad, stats, ctx)
        return (sub if idx is None else idx[sub]), f, g
    elif isinstance(node, Warp):
        f, g = _warp(node, P, need_grad, prune, stats, ctx)
    else:
        f, g = _op(node, P, need_grad, prune, stats, ctx)
    return idx, f, g


_EMPTY = np.zeros(0, np.int64)
_EMPTY_F = np.zeros(0)
_EMPTY_G = np.zeros((3, 0))


def _warp(node, P, need_grad, prune, stats, ctx):
    Q, J = node.to_child(P, need_grad)
    f, gq = evaluate(node.child, Q, need_grad, prune, stats, ctx)
    if not need_grad:
        return f, None
    if J.ndim == 2:
        return f, J.T @ gq                       # grad_p = J^T grad_q
    return f, np.einsum("kin,kn->in", J, gq)


def _op(node, P, need_grad, prune, stats, ctx):
    n = P.shape[1]
    box = _box(P) if prune and n else None
    kids = [_sparse(c, P, need_grad, prune, stats, box, ctx) for c in node.children]
    return combine(node, kids, n, need_grad, ctx)


def combine(node, kids, n, need_grad, ctx=None):
    """An operator's field and gradient from its children's (idx, f, g)."""
    op = node.op
    if op == "blend":
        return _sum(kids, n, need_grad)
    if op in ("union", "intersection"):
        return _extreme(kids, n, need_grad, np.greater if op == "union" else np.less, ctx, node)
    if op == "difference":
        A, gA = _dense(kids[0], n, need_grad)
        M, gM = _extreme(kids[1:], n, need_grad, np.greater, ctx, node, part=1)
        B = 2 * node.iso - M
        first = A <= B
        if ctx is not None:         # the first child (0) or the subtracted ones (1), recorded or pinned
            first = ctx.decide(node, np.where(first, 0, 1)) == 0
        F = np.where(first, A, B)
        return F, (np.where(first, gA, -gM) if need_grad else None)
    return _ricci(kids, n, need_grad, node.n)


def _stack(node, P, need_grad, stats, ctx=None):
    """A Stack at P (3, n): (idx, f, g) over the points some member's box holds."""
    pp, kk = node.pairs(P)
    if len(pp) == 0:
        return _EMPTY, _EMPTY_F, (_EMPTY_G if need_grad else None)
    f, g = _shape(node.shape, P.take(pp, axis=1), kk, need_grad, stats, None if ctx is None else ctx.pairs(pp, kk))
    # pairs are sorted by point, then by member
    if node.reduce == "sum":
        starts = np.flatnonzero(np.diff(pp, prepend=-1))
        F = np.add.reduceat(f, starts)
        return pp[starts], F, (np.add.reduceat(g, starts, axis=1) if need_grad else None)
    # a union: the largest member value; a member whose box misses the point is 0 there
    owners, F, win = G.segment_max(pp, f, need_grad or ctx is not None)
    zero = (np.bincount(pp)[owners] < node.K) & (F < 0.0)
    if ctx is not None:
        n = P.shape[1]
        w = np.full(n, BR.ZERO, np.int64)
        w[owners] = np.where(zero, BR.ZERO, kk[win])
        forced = BR.forced(ctx, node, w)
        if forced is not None:
            F, Gr = BR.pair_choice(n, pp, kk, f, g, forced)
            # the stack covers the points it covers unpinned and those pinned to another
            # choice (whatever other points of the batch are pinned to: a parent's
            # choice where every child is 0 depends on which children cover the point)
            cover = forced != w
            cover[owners] = True
            sub = np.flatnonzero(cover)
            return sub, F[sub], (Gr[:, sub] if need_grad else None)
    F[zero] = 0.0
    if not need_grad:
        return owners, F, None
    Gr = g.take(win, axis=1)
    Gr[:, zero] = 0.0
    return owners, F, Gr


def _shape(t, P, kk, need_grad, stats, ctx=None):
    """A stacked shape at pair points P (3, v), pair p belonging to member kk[p]: every
    position is evaluated densely (a member is 0 outside its support)."""
    v = P.shape[1]
    if isinstance(t, StackedGroup):
        if t.m == 1:            # one pair per point, member kk; _single as for one member
            return G.evaluate_pairs(t.prm, t.reduce, t.n, P, kk, None, v, need_grad, stats)
        pp, idx, counts = t.pairs(P, kk)
        return G.evaluate_pairs(t.prm, t.reduce, t.n, P.take(pp, axis=1), idx, pp, v, need_grad, stats,
                                ctx, t, t.m if t.dense(v) else None)
    kids = [(None, *_shape(c, P, kk, need_grad, stats, ctx)) for c in t.children]
    return combine(t, kids, v, need_grad, ctx)


def _dense(kid, n, need_grad):
    idx, f, g = kid
    if idx is None:
        return f, g
    F = np.zeros(n)
    F[idx] = f
    G = None
    if need_grad:
        G = np.zeros((3, n))
        G[:, idx] = g
    return F, G


def _sum(kids, n, need_grad):
    F = np.zeros(n)
    G = np.zeros((3, n)) if need_grad else None
    for idx, f, g in kids:
        if idx is None:
            F += f
            if need_grad:
                G += g
        else:
            F[idx] += f
            if need_grad:
                G[:, idx] += g
    return F, G


def _extreme(kids, n, need_grad, better, ctx=None, node=None, part=0):
    """max (better=np.greater) or min (np.less) over children that are 0 outside their
    support; the first child wins ties, as argmax/argmin would. With ``ctx`` the
    choice (the child, or ZERO) is recorded or pinned (model.branches)."""
    F = np.full(n, -np.inf if better is np.greater else np.inf)
    G = np.zeros((3, n)) if need_grad else None
    w = None if ctx is None else np.full(n, BR.ZERO, np.int64)
    cover = np.zeros(n, np.int32)
    for k, (idx, f, g) in enumerate(kids):
        if idx is not None and len(idx) == 0:
            continue                              # covers no point: 0 everywhere, as "partial" handles
        if idx is None:
            win = better(f, F)
            F = np.where(win, f, F)
            if need_grad:
                G = np.where(win, g, G)
            if w is not None:
                w[win] = k
            cover += 1
        else:
            cur = F[idx]
            win = better(f, cur)
            F[idx] = np.where(win, f, cur)
            if need_grad:
                G[:, idx] = np.where(win, g, G.take(idx, axis=1))
            if w is not None:
                w[idx[win]] = k
            cover[idx] += 1
    # a child that does not cover a point is 0 there
    partial = cover < len(kids)
    if partial.any():
        zero_wins = partial & better(0.0, F)
        F[zero_wins] = 0.0
        if need_grad:
            G[:, zero_wins] = 0.0
        if w is not None:
            w[zero_wins] = BR.ZERO
    if ctx is not None:
        forced = BR.forced(ctx, node, w, part)
        if forced is not None:
            return BR.child_choice(kids, n, need_grad, forced)
    return F, G


def _ricci(kids, n, need_grad, nexp):
    S = np.zeros(n)
    Wg = np.zeros((3, n)) if need_grad else None
    for idx, f, g in kids:
        fp = np.maximum(f, 0.0)
        sl = slice(None) if idx is None else idx
        S[sl] += fp ** nexp
        if need_grad:
            Wg[:, sl] += fp ** (nexp - 1.0) * g
    F = S ** (1.0 / nexp)
    if not need_grad:
        return F, None
    with np.errstate(divide="ignore", invalid="ignore"):
        c = np.where(F > 0, F ** (1.0 - nexp), 0.0)
    return F, c * Wg
