"""Which primitive makes the surface where: the owner of a point is the primitive whose
field decides the model's value there (in a blend or a union the child with the largest
value, in an intersection the smallest, in a difference the side that wins), found down
the one-to-one plan of the tree. And each primitive's way into the model: the warps
above it, which carry points from its own coordinates to the model's.

Primitives are numbered in the tree's depth-first order (model.nodes.iter_nodes), which
is the order of :func:`primitives`.
"""
from dataclasses import dataclass

import numpy as np

from . import evaluate as E
from .groups import Group
from .plan import compile_plan
from .plan_nodes import Warp

NONE = -1                  # no primitive reaches the point


@dataclass(frozen=True)
class Placed:
    """A primitive of the tree (model.nodes), the warps from its coordinates to the
    model's (innermost first) and its support box in its own coordinates."""
    node: object
    warps: tuple
    lo: np.ndarray
    hi: np.ndarray

    def same(self, other):
        """The same primitive in the same place."""
        return self.node == other.node and len(self.warps) == len(other.warps) and \
            all(a.same(b) for a, b in zip(self.warps, other.warps))

    def box(self):
        """A box of the model's coordinates outside which the primitive's field is 0."""
        lo, hi = self.lo, self.hi
        for w in self.warps:
            lo, hi = w.image(lo, hi)
        return lo, hi

    def to_model(self, Q):
        """Points Q (n, 3) of the primitive's coordinates in the model's."""
        P = np.ascontiguousarray(np.asarray(Q, float).T)
        for w in self.warps:
            P = w.from_child(P)
        return P.T

    def to_local(self, P):
        """Points P (n, 3) of the model in the primitive's own coordinates."""
        Q = np.ascontiguousarray(np.asarray(P, float).T)
        for w in reversed(self.warps):
            Q, _ = w.to_child(Q, False)
        return Q.T

    def area_scale(self):
        """How the warps scale the primitive's areas (approximately, where they bend)."""
        return float(np.prod([w.area_scale() for w in self.warps])) if self.warps else 1.0


def owners(ev):
    """The Owners of an evaluator's model, made once (kept with the evaluator's results
    that depend on its model alone)."""
    if "owners" not in ev.memo:
        ev.memo["owners"] = Owners(ev.model)
    return ev.memo["owners"]


class Owners:
    """The primitives of a model (:attr:`placed`, numbered depth first) and the owner of
    points (:meth:`of`)."""

    def __init__(self, model):
        self.iso = model.iso
        self.plan = compile_plan(model, optimize=False)
        self.placed = []
        self._index = {}
        todo = [(self.plan, ())]
        while todo:
            node, warps = todo.pop()
            if isinstance(node, Group):
                self._index[id(node)] = len(self.placed)
                self.placed.append(Placed(node.sources[0], warps, node.lo, node.hi))
            elif isinstance(node, Warp):
                todo.append((node.child, (node,) + warps))
            else:
                todo.extend((c, warps) for c in reversed(node.children))

    def of(self, P):
        """The owner of each point of P (n, 3): a primitive's number, or NONE."""
        P = E.as_points(P)
        owner = np.full(len(P), NONE, np.int64)
        for a in range(0, len(P), E.CHUNK):
            cols = np.ascontiguousarray(P[a:a + E.CHUNK].T)
            idx, _, who = self._sparse(self.plan, cols)
            if idx is None:
                owner[a:a + E.CHUNK] = who
            else:
                owner[a + idx] = who
        return owner

    def _sparse(self, node, P):
        """(idx, f, owner) at the columns idx of P (None: all); elsewhere f is 0 and
        nothing owns the point."""
        lo, hi = node.lo, node.hi
        inside = np.all((P >= lo[:, None]) & (P <= hi[:, None]), axis=0)
        idx = None
        if not inside.all():
            idx = np.flatnonzero(inside)
            P = P.take(idx, axis=1)
        n = P.shape[1]
        if n == 0:
            return idx, np.zeros(0), np.zeros(0, np.int64)
        if isinstance(node, Group):
            f, _ = node.evaluate(P, False)
            who = np.full(n, self._index[id(node)], np.int64)
        elif isinstance(node, Warp):
            Q, _ = node.to_child(P, False)
            f, who = self._dense(node.child, Q)
        else:
            f, who = self._op(node, P)
        return idx, f, who

    def _dense(self, node, P):
        idx, f, who = self._sparse(node, P)
        if idx is None:
            return f, who
        F = np.zeros(P.shape[1])
        W = np.full(P.shape[1], NONE, np.int64)
        F[idx], W[idx] = f, who
        return F, W

    def _op(self, node, P):
        n = P.shape[1]
        kids = [self._sparse(c, P) for c in node.children]
        F, _ = E.combine(node, [(i, f, None) for i, f, _ in kids], n, False)     # the evaluator's own value
        if node.op == "difference":
            A, first = _best(kids[:1], n, np.greater)
            M, sub = _best(kids[1:], n, np.greater)
            return F, np.where(A <= 2 * node.iso - M, first, sub)
        return F, _best(kids, n, np.less if node.op == "intersection" else np.greater)[1]


def _best(kids, n, better):
    """The largest (``better`` np.greater) or smallest value of children (idx, f, owner),
    0 where a child does not reach, and its owner (the first child wins ties)."""
    value = np.zeros(n)
    owner = np.full(n, NONE, np.int64)
    for k, (idx, f, who) in enumerate(kids):
        if idx is None:
            take = better(f, value) | (k == 0)
            value[take], owner[take] = f[take], who[take]
        else:
            if k == 0:                      # the first child is 0 where it does not reach
                owner[:] = NONE
            take = better(f, value[idx]) | (k == 0)
            value[idx[take]], owner[idx[take]] = f[take], who[take]
    return value, owner
