"""What changed between two frames' models, for a session that goes on from the last
frame's (agents.continuation): nothing; everything (the tree's shape, an operator's
exponent or the iso value changed); or the primitives that moved or changed, as the
boxes of their support before and after. Outside those boxes the field is the same,
and so is every crease there, and every silhouette seen from the same eye."""
import numpy as np

from ..model import nodes as N
from ..model.owners import Owners

EVERYWHERE = "everywhere"


class Boxes:
    """Boxes (m, 3) lo and hi: the parts of space where the field changed."""

    def __init__(self, lo, hi):
        self.lo, self.hi = np.asarray(lo, float).reshape(-1, 3), np.asarray(hi, float).reshape(-1, 3)

    def __len__(self):
        return len(self.lo)

    def contains(self, P, pad=0.0):
        """Which points lie in a box (grown by ``pad``)."""
        P = np.atleast_2d(np.asarray(P, float))
        out = np.zeros(len(P), bool)
        for lo, hi in zip(self.lo - pad, self.hi + pad):
            out |= np.all((P >= lo) & (P <= hi), axis=1)
        return out


def changed(old, new):
    """None where the models (model.nodes.Model) are the same, EVERYWHERE where the
    tree's shape, an exponent or the iso differ, else the :class:`Boxes` of the
    primitives that changed (their support before and after)."""
    if old == new:
        return None
    if old.iso != new.iso or not _same_shape(old.root, new.root):
        return EVERYWHERE
    before, after = Owners(old).placed, Owners(new).placed
    boxes = [p.box() for a, b in zip(before, after) if not a.same(b) for p in (a, b)]
    if not boxes:
        return None                     # only names differ
    lo, hi = zip(*boxes)
    if not (np.all(np.isfinite(lo)) and np.all(np.isfinite(hi))):
        return EVERYWHERE
    return Boxes(lo, hi)


def _same_shape(a, b):
    """The same node types in the same places, with the same operators' exponents (the
    primitives' and warps' values aside)."""
    todo = [(a, b)]
    while todo:
        x, y = todo.pop()
        if type(x) is not type(y):
            return False
        if isinstance(x, N.Ricci) and x.n != y.n:
            return False
        kids_x, kids_y = _children(x), _children(y)
        if len(kids_x) != len(kids_y):
            return False
        todo.extend(zip(kids_x, kids_y))
    return True


def _children(node):
    if isinstance(node, (N.Transform, N.Twist, N.Taper, N.Bend)):
        return (node.child,)
    return getattr(node, "children", ())
