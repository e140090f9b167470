"""Field and gradient of a compiled plan on (N,3) float64 batches.

One evaluation path: a single point is a batch of one, and the naive reference (every
node on every point) runs the same functions on the unoptimised plan with pruning off.
With pruning on, every plan node first drops the points outside its support box, so a
subtree only ever sees the points that can feel it.
"""
import numpy as np

from . import warps as W
from .groups import Group
from .plan import Op, Warp, compile_plan

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
        lo, hi = self.plan.lo, self.plan.hi
        self.bounds = (lo.copy(), hi.copy())
        finite = np.all(np.isfinite(lo)) and np.all(np.isfinite(hi)) and np.all(hi >= lo)
        self.scale = float(np.linalg.norm(hi - lo)) if finite else 1.0

    def field(self, P):
        return self._run(P, False)[0]

    def field_grad(self, P):
        return self._run(P, True)

    def _run(self, P, need_grad):
        P = as_points(P)
        n = len(P)
        self.stats.points += n
        F = np.empty(n)
        G = np.empty((n, 3)) if need_grad else None
        for a in range(0, n, CHUNK):
            f, g = evaluate(self.plan, P[a:a + CHUNK], need_grad, self.prune, self.stats)
            F[a:a + CHUNK] = f
            if need_grad:
                G[a:a + CHUNK] = g
        return F, G


def _inside(P, lo, hi):
    return np.all((P >= lo) & (P <= hi), axis=1)


def evaluate(node, P, need_grad, prune=True, stats=None):
    n = len(P)
    if prune:
        mask = _inside(P, node.lo, node.hi)
        if not mask.all():
            F = np.zeros(n)
            G = np.zeros((n, 3)) if need_grad else None
            if mask.any():
                f, g = _dispatch(node, P[mask], need_grad, prune, stats)
                F[mask] = f
                if need_grad:
                    G[mask] = g
            return F, G
    return _dispatch(node, P, need_grad, prune, stats)


def _dispatch(node, P, need_grad, prune, stats):
    if isinstance(node, Group):
        return node.evaluate(P, need_grad, stats)
    if isinstance(node, Warp):
        return _warp(node, P, need_grad, prune, stats)
    return _op(node, P, need_grad, prune, stats)


def _warp(node, P, need_grad, prune, stats):
    p = node.params
    if node.kind == "affine":
        Q, J = W.affine_map(P, p["A"], p["b"], need_grad)
    elif node.kind == "twist":
        Q, J = W.twist_map(P, p["rate"], need_grad)
    elif node.kind == "taper":
        Q, J = W.taper_map(P, p["rate"], need_grad)
    else:
        Q, J = W.bend_map(P, p["rate"], need_grad)
    f, gq = evaluate(node.child, Q, need_grad, prune, stats)
    if not need_grad:
        return f, None
    if J.ndim == 2:
        return f, gq @ J
    return f, np.einsum("nki,nk->ni", J, gq)


def _op(node, P, need_grad, prune, stats):
    res = [evaluate(c, P, need_grad, prune, stats) for c in node.children]
    op = node.op
    if op == "blend":
        F = res[0][0].copy()
        for f, _ in res[1:]:
            F += f
        if not need_grad:
            return F, None
        G = res[0][1].copy()
        for _, g in res[1:]:
            G += g
        return F, G
    fs = np.stack([r[0] for r in res])
    rows = np.arange(fs.shape[1])
    if op in ("union", "intersection"):
        k = np.argmax(fs, axis=0) if op == "union" else np.argmin(fs, axis=0)
        F = fs[k, rows]
        return F, (np.stack([r[1] for r in res])[k, rows] if need_grad else None)
    if op == "difference":
        A = fs[0]
        others = fs[1:]
        j = np.argmax(others, axis=0)
        B = 2 * node.iso - others[j, rows]
        first = A <= B
        F = np.where(first, A, B)
        if not need_grad:
            return F, None
        gs = np.stack([r[1] for r in res[1:]])
        return F, np.where(first[:, None], res[0][1], -gs[j, rows])
    # ricci: (sum max(f,0)^n)^(1/n)
    nexp = node.n
    fp = np.maximum(fs, 0.0)
    F = (fp ** nexp).sum(0) ** (1.0 / nexp)
    if not need_grad:
        return F, None
    w = fp ** (nexp - 1.0)
    Wg = np.einsum("kn,knj->nj", w, np.stack([r[1] for r in res]))
    with np.errstate(divide="ignore", invalid="ignore"):
        c = np.where(F > 0, F ** (1.0 - nexp), 0.0)
    return F, c[:, None] * Wg
