"""Compile a BlobTree into an evaluation plan with support bounds on every node.

The optimised plan (the default) folds rigid and uniformly scaled transforms into the
primitives below them, flattens nested operators of one kind and gathers the primitive
children of each blend, union and ricci into vectorised :class:`~.groups.Group`s (the
subtracted children of a difference are pooled as their union, which is all a
difference takes of them); at least three structurally identical operator subtrees of
one union or blend (a train's wheels) become one :class:`~.stack.Stack`. The naive
plan maps the tree one to one (every node, every point): it is the reference the
optimised plan must equal, and the baseline of ``bench/field.py``.

Support bounds are conservative boxes, in each node's input coordinates, outside of
which the node's field is exactly 0; value bounds ``[vlo, vhi]`` make that sound for
intersection and difference (see :func:`.plan_nodes._op_bounds`).
"""
import numpy as np

from . import nodes as N
from . import primitives as PR
from . import warps as W
from .groups import Group
from .plan_nodes import Op, Warp
from .stack import stack_children

_REDUCE = {"blend": "sum", "union": "max", "ricci": "ricci"}


def _is_similarity(M):
    s2 = (abs(float(np.linalg.det(M))) ** (1 / 3)) ** 2
    if not s2 > 0:
        return False
    D = M.T @ M
    D.flat[::4] -= s2                   # M^T M = s^2 I (np.allclose cost a shell's compile 40 ms)
    return float(np.abs(D).max()) <= 1e-12 * max(s2, 1.0)


class _Builder:
    def __init__(self, iso, optimize):
        self.iso, self.optimize = iso, optimize

    def build(self, node, M=None, t=None):
        """Plan for ``node`` seen through the similarity p = M q + t (optimised plans)."""
        if isinstance(node, tuple(N.PRIMITIVES.values())):
            if M is not None:
                folded = PR.fold_similarity(node, M, t)
                if folded is None:
                    return self._affine(Group([node], use_grid=False), M, t)
                node = folded
            return Group([node], use_grid=False)
        if isinstance(node, N.Transform):
            L, tt = W.transform_matrix(node.translate, node.rotate, node.scale)
            if M is not None:
                L, tt = M @ L, M @ tt + t
            if self.optimize and _is_similarity(L):
                return self.build(node.child, L, tt)
            return self._affine(self.build(node.child), L, tt)
        if isinstance(node, (N.Twist, N.Taper, N.Bend)):
            kind = N.TYPE_NAME[type(node)]
            inner = Warp(kind, self.build(node.child), rate=float(node.rate))
            return inner if M is None else self._affine(inner, M, t)
        op = N.TYPE_NAME[type(node)]
        kids = [self.build(c, M, t) for c in node.children]
        n = getattr(node, "n", 1.0)
        if self.optimize:
            kids = self._flatten(op, n, kids)
            kids = self._group(op, n, kids)
            if op == "difference" and len(kids) > 2:
                # the subtracted children act as their union (max): pool them like one
                sub = self._group("union", 1.0, self._flatten("union", 1.0, kids[1:]))
                kids = [kids[0], sub[0] if len(sub) == 1 else Op("union", sub, self.iso)]
            if len(kids) == 1 and op in ("blend", "union", "intersection"):
                return kids[0]
        return Op(op, kids, self.iso, n)

    def _affine(self, child, L, t):
        A, b = W.affine_inverse(L, t)
        return Warp("affine", child, A=A, b=b, L=L, t=t)

    @staticmethod
    def _flatten(op, n, kids):
        if op not in ("blend", "union", "intersection", "ricci"):
            return kids
        out = []
        for k in kids:
            if isinstance(k, Op) and k.op == op and (op != "ricci" or k.n == n):
                out.extend(k.children)
            else:
                out.append(k)
        return out

    @staticmethod
    def _group(op, n, kids):
        """Pool the primitives of an n-ary node's groups by kind into one group each:
        sums of sums (blend), maxima of non-negative maxima (union), Ricci sums with
        the same exponent."""
        if op not in _REDUCE:
            return kids
        reduce = _REDUCE[op]
        by_kind, rest = {}, []
        for k in kids:
            same = isinstance(k, Group) and (k.reduce == reduce and (reduce != "ricci" or k.n == n)
                                             or k.m == 1 and k.reduce == "sum")
            if same and (reduce == "sum" or float(k.prm["S"].min()) >= 0):
                by_kind.setdefault(k.kind, []).extend(k.sources)
            else:
                rest.append(k)
        groups = [Group(prims, reduce=reduce, n=n) for prims in by_kind.values()]
        return groups + rest


def compile_plan(model, optimize=True):
    plan = _Builder(model.iso, optimize).build(model.root)
    return _stack(plan) if optimize else plan


def _stack(node):
    """Stack identical subtrees of every union and blend, once nested operators of one
    kind are flattened (a stack replaces its members: the node's bounds stay as they
    are, being the union box and the max or sum of the same members' bounds)."""
    if isinstance(node, Warp):
        node.child = _stack(node.child)
    elif isinstance(node, Op):
        node.children = [_stack(c) for c in node.children]
        if node.op in ("blend", "union"):
            node.children = stack_children(node.children, _REDUCE[node.op])
    return node
