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
    """The outlines with their segments longer than LONG of their steps ``bridges``
    (per outline, the step of each segment, a closed one's last running to its first
    point; empty: none) replaced by outline points FILL of the outline's step apart."""
    jobs = []               # (outline, segment, interior points, segment length)
    C, W, K = [], [], []
    for k, o in enumerate(outlines):
        if o.step <= 0 or len(o.points) < 2 or len(bridges[k]) == 0:
            continue
        P = np.vstack([o.points, o.points[:1]]) if o.closed else o.points
        N = np.vstack([o.normals, o.normals[:1]]) if o.closed else o.normals
        d = np.diff(P, axis=0)
        length = np.linalg.norm(d, axis=1)
        for s in np.flatnonzero(length > LONG * np.asarray(bridges[k], float)).tolist():
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
    out = list(outlines)
    fills = {}
    at = 0
    for k, s, m, length in jobs:
        rows = slice(at, at + m)
        at += m
        o = outlines[k]
        P = np.vstack([o.points, o.points[:1]]) if o.closed else o.points
        along = (X[rows] - P[s]) @ (P[s + 1] - P[s]) / length ** 2
        if valid[rows].all() and np.all(np.diff(np.r_[0.0, along, 1.0]) > 0) and \
                np.all(np.linalg.norm(X[rows] - C[rows], axis=1) <= width[rows] * length):
            fills.setdefault(k, []).append((s, X[rows], n[rows]))
    for k, parts in fills.items():
        o = out[k]
        P, N = [], []
        cut = 0
        for s, X, n in sorted(parts, key=lambda p: p[0]):
            P += [o.points[cut:s + 1], X]
            N += [o.normals[cut:s + 1], n]
            cut = s + 1
        P.append(o.points[cut:])
        N.append(o.normals[cut:])
        out[k] = Outline(o.kind, np.concatenate(P), np.concatenate(N), o.closed, o.step)
    return out
