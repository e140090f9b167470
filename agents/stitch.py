"""Stitch outline fragments traced by different agents into whole polylines.

Agents trace one curve from several seeds at once and stop where they meet another's
trace, so a curve arrives in pieces; pieces of one kind whose ends lie within ``gap``
are joined (reversing pieces as needed), and a polyline whose two ends meet is closed.
"""
import numpy as np


def stitch(outlines, gap, make):
    """``outlines``: objects with kind, points, normals, closed; ``make(kind, P, N,
    closed)`` builds a result."""
    out = []
    for kind in sorted({o.kind for o in outlines}):
        pieces = [(o.points, o.normals) for o in outlines if o.kind == kind and not o.closed]
        out += [make(kind, o.points, o.normals, True) for o in outlines if o.kind == kind and o.closed]
        while pieces:
            P, N = pieces.pop(0)
            grown = True
            while grown:
                grown = False
                best = None
                for j, (Q, M) in enumerate(pieces):
                    for flip_self, flip_other in ((False, False), (False, True), (True, False), (True, True)):
                        a = P[0] if flip_self else P[-1]
                        b = Q[-1] if flip_other else Q[0]
                        d = np.linalg.norm(a - b)
                        if d < gap and (best is None or d < best[0]):
                            best = (d, j, flip_self, flip_other)
                if best is not None:
                    _, j, fs, fo = best
                    Q, M = pieces.pop(j)
                    if fs:
                        P, N = P[::-1], N[::-1]
                    if fo:
                        Q, M = Q[::-1], M[::-1]
                    P, N = np.vstack([P, Q]), np.vstack([N, M])
                    grown = True
            closed = len(P) > 3 and np.linalg.norm(P[0] - P[-1]) < gap
            if closed:
                P, N = P[:-1], N[:-1] if np.linalg.norm(P[0] - P[-1]) < 1e-12 else N[:-1]
            out.append(make(kind, P, N, closed))
    return out
