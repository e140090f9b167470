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

The columns: one per union/intersection operator, union group (of more than one
primitive) and union stack; two per difference (first child or the subtracted ones,
and the subtracted ones' own max); sites inside a stack's shared shape have one column
per stack member.
"""
import numpy as np

NOT_REACHED = -2
ZERO = -1


class Sites:
    """Column numbers of a plan's decision sites: ``col[id(node)] = (first, per)``,
    ``per`` the columns of one part (a stack's member count inside its shape, else 1)."""

    def __init__(self, plan):
        from .groups import Group
        from .plan import Op, Warp
        from .stack import Stack, StackedGroup, StackedOp
        self.col = {}
        self.count = 0

        def add(node, per, parts=1):
            self.col[id(node)] = (self.count, per)
            self.count += per * parts

        todo = [(plan, 1)]
        while todo:
            node, per = todo.pop()
            if isinstance(node, (Group, StackedGroup)):
                if node.reduce == "max" and node.m > 1:
                    add(node, per)
            elif isinstance(node, Stack):
                if node.reduce == "max":
                    add(node, per)
                todo.append((node.shape, node.K))
            elif isinstance(node, Warp):
                todo.append((node.child, per))
            elif isinstance(node, (Op, StackedOp)):
                if node.op in ("union", "intersection"):
                    add(node, per)
                elif node.op == "difference":
                    add(node, per, parts=2)
                todo.extend((c, per) for c in node.children)
        self._plan = plan          # the ids above are of this plan's nodes: keep it alive


class Ctx:
    """The record (``pin`` False: choices are written) or the pins (True: read) of an
    evaluation, for the points in hand: ``ids`` their rows of the table, ``off`` their
    stack member inside a stack's shape (None outside)."""
    __slots__ = ("sites", "table", "ids", "off", "pin")

    def __init__(self, sites, table, ids, off=None, pin=False):
        self.sites, self.table, self.ids, self.off, self.pin = sites, table, ids, off, pin

    def sub(self, idx):
        return Ctx(self.sites, self.table, self.ids[idx], None if self.off is None else self.off[idx], self.pin)

    def pairs(self, pp, kk):
        assert self.off is None, "a stack inside a stack's shape"
        return Ctx(self.sites, self.table, self.ids[pp], kk, self.pin)

    def decide(self, node, natural, part=0):
        """Record the natural choices, or return them with the pinned ones put in."""
        first, per = self.sites.col[id(node)]
        cols = first + part * per
        if self.off is not None:
            cols = cols + self.off
        if not self.pin:
            self.table[self.ids, cols] = natural
            return natural
        forced = self.table[self.ids, cols]
        return np.where(forced == NOT_REACHED, natural, forced)


def extreme(kids, n, need_grad, better, ctx, node, part=0):
    """The max (better=np.greater) or min (np.less) of children (idx, f, g) that are 0
    outside their support, as evaluate._extreme computes it (first child wins ties; a
    child that covers no point is skipped but still makes every point partial), with
    the choice recorded or pinned. Two passes over the children, O(n) memory (a union
    of a thousand subtrees must not need a (children, 3, n) array)."""
    F = np.full(n, -np.inf if better is np.greater else np.inf)
    w = np.full(n, ZERO, np.int64)
    cover = np.zeros(n, np.int32)
    for k, (idx, f, g) in enumerate(kids):
        if idx is not None and len(idx) == 0:
            continue
        sl = slice(None) if idx is None else idx
        cur = F[sl]
        win = better(f, cur)
        F[sl] = np.where(win, f, cur)
        w[sl] = np.where(win, k, w[sl])
        cover[sl] += 1
    w[(cover < len(kids)) & better(0.0, F)] = ZERO           # a child not covering a point is 0 there
    w = ctx.decide(node, w, part)
    F = np.zeros(n)
    G = np.zeros((3, n)) if need_grad else None
    for k, (idx, f, g) in enumerate(kids):
        mine = w == k if idx is None else w[idx] == k
        to = np.flatnonzero(mine) if idx is None else idx[mine]
        F[to] = f[mine]
        if need_grad:
            G[:, to] = g[:, mine]
    return F, G


def difference(A, gA, M, gM, iso, ctx, node):
    """min(A, 2 iso - M) (A: the first child, M: the subtracted ones' max), choice 0
    (the first child) or 1, recorded or pinned."""
    B = 2 * iso - M
    w = ctx.decide(node, np.where(A <= B, 0, 1).astype(np.int32))
    first = w == 0
    return np.where(first, A, B), (np.where(first, gA, -gM) if gA is not None else None)


def pair_max(n, pp, member, f, g, natural, ctx, node):
    """A union over (point, member) pairs (sorted by point; ``member`` the choice each
    pair stands for, one pair per point and member) as dense (n,) values and (3, n)
    gradients: the pair of each point's choice (``natural``: its largest pair, or ZERO),
    recorded or pinned; 0 where a point has no pair with its choice."""
    w = ctx.decide(node, natural)
    hit = member == w[pp]
    F = np.zeros(n)
    F[pp[hit]] = f[hit]
    G = None
    if g is not None:
        G = np.zeros((3, n))
        G[:, pp[hit]] = g[:, hit]
    return F, G
