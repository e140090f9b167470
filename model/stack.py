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
from .groups import Group

STACK_MIN = 3                 # fewer identical subtrees are left as they are
PAIR_BLOCK = 1 << 22          # booleans per block of the (point, member) box test
STACK_MAX_PRIMS = 16          # larger subtrees keep their own spatial pruning (a stack
                              # evaluates every primitive of a member on each of its points)


def signature(node):
    """A hashable description of a plan node's shape, or None when it cannot be stacked
    (warps, and bare groups, which the plan already pools by kind)."""
    from .plan import Op
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
    return sig[2] if sig[0] == "group" else sum(_prims(k) for k in sig[4])


class StackedGroup:
    """The groups at one position of every member: K * m primitives, member k's at
    rows k*m .. k*m + m - 1."""

    def __init__(self, groups):
        self.m = groups[0].m
        self.reduce, self.n = groups[0].reduce, groups[0].n
        self.prm = PR.pack([p for g in groups for p in g.sources])


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

    def __repr__(self):
        return f"Stack({self.K} x {self.shape.op}, {self.reduce})"

    def pairs(self, P):
        """(point, member) pairs whose member box holds the point, sorted by point
        (tested in blocks of points, so that a stack of thousands of members never
        needs more than PAIR_BLOCK booleans at a time)."""
        n = P.shape[1]
        step = max(1, PAIR_BLOCK // self.K)
        pp, kk = [], []
        for a in range(0, n, step):
            Q = P[:, a:a + step]
            inside = np.ones((Q.shape[1], self.K), bool)
            for k in range(3):
                x = Q[k][:, None]
                inside &= (x >= self.member_lo[None, :, k]) & (x <= self.member_hi[None, :, k])
            i, j = np.nonzero(inside)
            pp.append(i + a)
            kk.append(j)
        if len(pp) == 1:
            return pp[0], kk[0]
        return (np.concatenate(pp), np.concatenate(kk)) if pp else (np.zeros(0, np.int64),) * 2


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
