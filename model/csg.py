"""Where a model's CSG creases are: the world-space centres of the primitives a
difference subtracts (a wheel's holes, a window's pocket). A crease runs where a
subtracted part's surface meets the part it is cut from; the rough polygonisation
misses the small ones, and agents start looking from these centres.

Primitives under a twist, taper or bend are left out (their skeletons are not in the
world frame); transforms are followed, iteratively (trees are at most
format.MAX_DEPTH deep, but a stack costs nothing)."""
import numpy as np

from . import nodes as N
from .warps import transform_matrix


def _centre(node):
    if isinstance(node, N.Segment):
        return 0.5 * (np.asarray(node.a, float) + np.asarray(node.b, float))
    return np.asarray(node.center, float)


def subtracted_centres(root):
    """(m, 3) centres of the primitives in the subtracted children of every
    difference, in the world frame."""
    out = []
    stack = [(root, np.eye(3), np.zeros(3), False)]
    while stack:
        node, L, t, sub = stack.pop()
        if isinstance(node, tuple(N.PRIMITIVES.values())):
            if sub:
                out.append(L @ _centre(node) + t)
        elif isinstance(node, N.Transform):
            L2, t2 = transform_matrix(node.translate, node.rotate, node.scale)
            stack.append((node.child, L @ L2, L @ t2 + t, sub))
        elif isinstance(node, N.Difference):
            stack.append((node.children[0], L, t, sub))
            stack.extend((c, L, t, True) for c in node.children[1:])
        elif isinstance(node, (N.Blend, N.Ricci, N.Union, N.Intersection)):
            stack.extend((c, L, t, sub) for c in node.children)
    return np.array(out, float).reshape(-1, 3)
