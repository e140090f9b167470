"""Joined outlines with their bridges filled: where pieces traced at two scales are
joined across a gap (agents.outline.across_scales), the join is a straight chord,
which cuts across a curve that bends (a small hole's silhouette joined to a piece
traced at the session's step: a chord over 40 degrees of its circle), and a piece's
own segments may be longer than its step (its pieces stitched across gaps). Each
segment longer than LONG of its step (a join's: the joined outline's, the finer) is
refined onto the outline: points FILL of the outline's step apart along the chord,
each bracketed across it in the surface's tangent plane and refined as a seed is
(agents.tracer.refine_seeds: exact outline points). A bridge whose points are not all found, in order along the chord, stays a
chord."""
import numpy as np

from ..blackboard.board import KIND_ID
from ..model.vectors import cross
from .outline import Outline
from .surface import unit
from .tracer import refine_seeds

LONG = 1.5          # a segment longer than this many of its steps is a bridge ...
FILL = 1.0          # ... filled with points this many of its outline's steps apart ...
ACROSS = (0.15, 0.5)  # ... each bracketed this share of the bridge's length to either side (the wider
                      # where the narrower holds no outline point)


def filled(surface, outlines, bridges, tol, crease_angle):
    """The outlines with their segments longer than LONG of their steps replaced by
    outline points FILL of the outline's step apart. ``bridges``: per outline, None or
    (the step of each segment, which segments must hold the line), a closed one's last
    segment running to its first point. Such a segment whose points are not all found
    is not the line's: the outline is cut there (a closed one opens, an open one
    splits); another segment so left stays a chord."""
    jobs = []               # (outline, segment, interior points, segment length)
    C, W, K = [], [], []
    for k, o in enumerate(outlines):
        if bridges[k] is None or o.step <= 0 or len(o.points) < 2:
            continue
        P = np.vstack([o.points, o.points[:1]]) if o.closed else o.points
        N = np.vstack([o.normals, o.normals[:1]]) if o.closed else o.normals
        d = np.diff(P, axis=0)
        length = np.linalg.norm(d, axis=1)
        for s in np.flatnonzero(length > LONG * np.asarray(bridges[k][0], float)).tolist():
            m = int(np.ceil(length[s] / (FILL * o.step)))
            t = np.arange(1, m)[:, None] / m
            c = P[s] + t * d[s]
            n = unit((1 - t) * N[s] + t * N[s + 1])
            jobs.append((k, s, len(c), length[s]))
            C.append(c)
            W.append(length[s] * unit(cross(n, np.broadcast_to(d[s], c.shape))))
            K += [KIND_ID[o.kind]] * len(c)
    if not jobs:
        return list(outlines)
    C, W, K = np.concatenate(C), np.concatenate(W), np.array(K)
    X, n, valid = np.zeros_like(C), np.zeros_like(C), np.zeros(len(C), bool)
    width = np.zeros(len(C))
    for share in ACROSS:
        todo = np.flatnonzero(~valid)
        seeds = refine_seeds(surface, K[todo], C[todo] - share * W[todo], C[todo] + share * W[todo], tol,
                             crease_angle)
        got = todo[seeds.valid]
        X[got], n[got], valid[got], width[got] = seeds.X[seeds.valid], seeds.n[seeds.valid], True, share
    fills, cuts = {}, {}
    at = 0
    for k, s, m, length in jobs:
        rows = slice(at, at + m)
        at += m
        o = outlines[k]
        P = np.vstack([o.points, o.points[:1]]) if o.closed else o.points
        along = (X[rows] - P[s]) @ (P[s + 1] - P[s]) / length ** 2
        if valid[rows].all() and np.all(np.diff(np.r_[0.0, along, 1.0]) > 0) and \
                np.all(np.linalg.norm(X[rows] - C[rows], axis=1) <= width[rows] * length):
            fills.setdefault(k, {})[s] = (X[rows], n[rows])
        elif bridges[k][1][s]:
            cuts.setdefault(k, set()).add(s)
    out = []
    for k, o in enumerate(outlines):
        if k in fills or k in cuts:
            out += _rebuilt(o, fills.get(k, {}), cuts.get(k, set()))
        else:
            out.append(o)
    return out


def _rebuilt(o, fills, cuts):
    """Outline o with its segments ``fills`` (segment -> points, normals) filled and cut
    at its segments ``cuts``: the pieces, in order."""
    n = len(o.points)
    order = list(range(n))
    if o.closed and cuts:                      # open it at its first cut: its pieces run on from there
        start = (min(cuts) + 1) % n
        order = order[start:] + order[:start]
    pieces, P, N = [], [], []
    for at, i in enumerate(order):
        P.append(o.points[i:i + 1])
        N.append(o.normals[i:i + 1])
        last = at == len(order) - 1
        if last and not o.closed:
            break
        if i in cuts:
            pieces.append((P, N))
            P, N = [], []
        elif i in fills and not (last and cuts):
            P.append(fills[i][0])
            N.append(fills[i][1])
    if P:
        pieces.append((P, N))
    closed = o.closed and not cuts
    return [Outline(o.kind, np.concatenate(p), np.concatenate(q), closed, o.step) for p, q in pieces]
