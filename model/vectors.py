"""Small vector helpers on (..., 3) batches."""
import numpy as np


def cross(a, b):
    """a x b over the last axis of (..., 3) arrays, broadcast, in float64: np.cross's
    products and differences, in the same order (for float64 input the same values to
    the bit), at a third of its cost on the small batches the agents' solvers step (its
    axis handling costs more than the arithmetic)."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    out = np.empty(np.broadcast_shapes(a.shape, b.shape))
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    np.subtract(a1 * b2, a2 * b1, out=out[..., 0])
    np.subtract(a2 * b0, a0 * b2, out=out[..., 1])
    np.subtract(a0 * b1, a1 * b0, out=out[..., 2])
    return out


def tangents(P, first, sizes):
    """Each point's direction along its line (central differences, one-sided at the
    ends; a line of one point: zero), of lines stored one after another in P with their
    ``first`` rows and ``sizes``."""
    nxt = np.arange(len(P)) + 1
    prv = np.arange(len(P)) - 1
    last = first + sizes - 1
    nxt[last] = last
    prv[first] = first
    T = P[nxt] - P[prv]
    return T / np.maximum(np.linalg.norm(T, axis=1, keepdims=True), 1e-300)
