"""Branch records: which child every max/min of a plan chose at each point, and
evaluation with those choices pinned.

A BlobTree's creases are where a union, intersection or difference (or the max of a
union group, or of a stack of unioned subtrees) switches from one child to another.
On each side of a crease the field is smooth: it is the field with that side's choices
fixed, and that field extends smoothly across the crease. ``Evaluator.record(P)``
evaluates as usual and notes every choice at every point (a row of int32 per point:
one column per decision site, ``NOT_REACHED`` where pruning kept the point away from
the site, ``ZERO`` where the zero outside every child's support won);
``Evaluator.pinned(P, rows)`` evaluates each point with the choices of its row where
the row reached the site (elsewhere, as usual). Two sheets' pinned fields and
gradients at one point are what Newton's method needs to put a point exactly on a
crease (the intersection of the two sheets), in a few evaluations instead of a
bisection's tens.

The columns (numbered by :class:`.sites.Sites`): one per union/intersection operator, union group (of more than one
primitive) and union stack; two per difference (first child or the subtracted ones,
and the subtracted ones' own max); sites inside a stack's shared shape have one column
per stack member.
"""
import numpy as np

NOT_REACHED = -2
ZERO = -1


def apart(a, b):
    """Whether the branch records a and b (rows of (m, sites)) chose differently at a
    site both reached (a site one of them never reached tells no switch): a crease may
    lie between the points."""
    return np.any((a != b) & (a != NOT_REACHED) & (b != NOT_REACHED), axis=1)


class Ctx:
    """The choices of an evaluation for the points in hand: ``ids`` their rows of the
    table, ``off`` their stack member inside a stack's shape (None outside). Each row's
    choices are pinned where it has them (not NOT_REACHED); with ``write`` every choice
    made is written into the table, so that a row of NOT_REACHED comes out as the
    point's record."""
    __slots__ = ("sites", "table", "ids", "off", "write")

    def __init__(self, sites, table, ids, off=None, write=False):
        self.sites, self.table, self.ids, self.off, self.write = sites, table, ids, off, write

    def at(self, ids):
        return Ctx(self.sites, self.table, ids, write=self.write)

    def sub(self, idx):
        return Ctx(self.sites, self.table, self.ids[idx], None if self.off is None else self.off[idx], self.write)

    def pairs(self, pp, kk):
        assert self.off is None, "a stack inside a stack's shape"
        return Ctx(self.sites, self.table, self.ids[pp], kk, self.write)

    def decide(self, node, natural, part=0):
        """The natural choices with the pinned ones put in (and written, with ``write``)."""
        first, per = self.sites.col[id(node)]
        cols = first + part * per
        if self.off is not None:
            cols = cols + self.off
        pinned = self.table[self.ids, cols]
        chosen = np.where(pinned == NOT_REACHED, natural, pinned)
        if self.write:
            self.table[self.ids, cols] = chosen
        return chosen


def forced(ctx, node, natural, part=0):
    """The choices at a site, natural ones recorded or pinned ones put in: the choices
    to evaluate instead (None: they are the natural ones, whose values the caller
    already has)."""
    w = ctx.decide(node, natural, part)
    return w if np.any(w != natural) else None


def child_choice(kids, n, need_grad, w):
    """Value and gradient of child w[i] of children (idx, f, g) at column i: 0 where w
    is ZERO or the child does not cover the point (its field is 0 there)."""
    F = np.zeros(n)
    G = np.zeros((3, n)) if need_grad else None
    for k, (idx, f, g) in enumerate(kids):
        mine = w == k if idx is None else w[idx] == k
        to = np.flatnonzero(mine) if idx is None else idx[mine]
        F[to] = f[mine]
        if need_grad:
            G[:, to] = g.compress(mine, axis=1)
    return F, G


def pair_choice(n, pp, member, f, g, w):
    """A union over (point, member) pairs (``member`` the choice each pair stands for,
    one pair per point and member) at each point's choice w: dense (n,) values and
    (3, n) gradients, 0 where w is ZERO or the point has no pair with that member."""
    hit = member == w[pp]
    F = np.zeros(n)
    F[pp[hit]] = f[hit]
    G = None
    if g is not None:
        G = np.zeros((3, n))
        G[:, pp[hit]] = g.compress(hit, axis=1)
    return F, G
