"""The nodes of an evaluation plan besides groups and stacks: an operator (:class:`Op`)
over its children and a warp (:class:`Warp`: an affine transform, twist, taper or bend)
of one child, each with its support box ``lo``, ``hi`` (outside it the node's field is
exactly 0, in the node's input coordinates) and value bounds ``vlo``, ``vhi`` (which
make those boxes sound for intersection and difference: see :func:`_op_bounds`).
Built by :mod:`.plan`."""
import numpy as np

from . import warps as W

INF = np.inf
EMPTY = (np.full(3, INF), np.full(3, -INF))


class Op:
    def __init__(self, op, children, iso, n=1.0):
        self.op, self.children, self.iso, self.n = op, list(children), iso, float(n)
        self.lo, self.hi, self.vlo, self.vhi = _op_bounds(self)

    def __repr__(self):
        return f"Op({self.op}, {len(self.children)} children)"


class Warp:
    def __init__(self, kind, child, **params):
        self.kind, self.child, self.params = kind, child, params
        self.lo, self.hi = self.image(child.lo, child.hi)
        self.vlo, self.vhi = child.vlo, child.vhi

    def image(self, lo, hi):
        """A box holding where the box (lo, hi) of the child's coordinates lands."""
        p = self.params
        if self.kind == "affine":
            return W.affine_bounds(lo, hi, p["L"], p["t"])
        if self.kind == "twist":
            return W.twist_bounds(lo, hi, p["rate"])
        if self.kind == "taper":
            return W.taper_bounds(lo, hi, p["rate"])
        return W.bend_bounds(lo, hi, p["rate"])

    def same(self, other):
        """The same warp (kind and parameters)."""
        return self.kind == other.kind and self.params.keys() == other.params.keys() and \
            all(np.array_equal(self.params[k], other.params[k]) for k in self.params)

    def __repr__(self):
        return f"Warp({self.kind})"

    def to_child(self, P, need_jac):
        """q = W^-1(p) at P (3, n), the point in the child's coordinates, and dq/dp
        ((3, 3), or (3, 3, n); None without ``need_jac``)."""
        p = self.params
        if self.kind == "affine":
            return W.affine_map(P, p["A"], p["b"], need_jac)
        if self.kind == "twist":
            return W.twist_map(P, p["rate"], need_jac)
        if self.kind == "taper":
            return W.taper_map(P, p["rate"], need_jac)
        return W.bend_map(P, p["rate"], need_jac)

    def from_child(self, Q):
        """p = W(q) at Q (3, n): where points of the child land."""
        p = self.params
        if self.kind == "affine":
            return p["L"] @ Q + p["t"][:, None]
        if self.kind == "twist":
            return W.twist_forward(Q, p["rate"])
        if self.kind == "taper":
            return W.taper_forward(Q, p["rate"])
        return W.bend_forward(Q, p["rate"])

    def area_scale(self):
        """How the warp scales areas, where that is a constant (affine: |det L|^(2/3));
        1 for the bending warps, which keep areas near their axis."""
        if self.kind == "affine":
            return abs(float(np.linalg.det(self.params["L"]))) ** (2.0 / 3.0)
        return 1.0


def _union_box(kids):
    return (np.min([k.lo for k in kids], axis=0), np.max([k.hi for k in kids], axis=0))


def _op_bounds(node):
    kids = node.children
    lo, hi = _union_box(kids)
    vl = [k.vlo for k in kids]
    vh = [k.vhi for k in kids]
    if node.op == "blend":
        return lo, hi, sum(vl), sum(vh)
    if node.op == "union":
        return lo, hi, max(vl), max(vh)
    if node.op == "ricci":
        return lo, hi, 0.0, float(sum(max(v, 0.0) ** node.n for v in vh) ** (1 / node.n))
    if node.op == "intersection":
        if min(vl) >= 0:   # outside any child's support that child is 0, so min is 0
            lo = np.max([k.lo for k in kids], axis=0)
            hi = np.min([k.hi for k in kids], axis=0)
            if np.any(lo > hi):
                lo, hi = EMPTY
        return lo, hi, min(vl), min(vh)
    if node.op == "difference":
        two_iso = 2 * node.iso
        m_lo, m_hi = max(vl[1:]), max(vh[1:])
        if m_hi <= two_iso:   # outside the first child: min(0, 2iso - max) = 0
            lo, hi = kids[0].lo, kids[0].hi
        return lo, hi, min(vl[0], two_iso - m_hi), min(vh[0], two_iso - m_lo)
    raise AssertionError(node.op)
