"""Join the points traced by different agents into whole polylines.

Agents trace one curve from several seeds at once and stop where they meet another's
trace, so a curve arrives in pieces that meet head to head, sometimes overlapping by a
step. All points of one kind are pooled, points closer than a third of a step merged,
and polylines are chained greedily: from a chain's end to the nearest unused point
within ``link`` that continues forward (positive dot product with the current
direction), then the same from the chain's other end. A chain whose ends meet is closed.
"""
import numpy as np


def stitch(outlines, link, make):
    out = []
    outlines = [o for o in outlines if len(o.points)]
    for kind in sorted({o.kind for o in outlines}):
        mine = [o for o in outlines if o.kind == kind]
        P = np.concatenate([o.points for o in mine])
        N = np.concatenate([o.normals for o in mine])
        P, N = _merge_close(P, N, link / 8.0)
        used = np.zeros(len(P), bool)
        while not used.all():
            start = int(np.flatnonzero(~used)[0])
            used[start] = True
            fwd = _walk(P, used, [start], link)
            bwd = _walk(P, used, [start] + fwd[:1], link, reverse_seed=True)
            idx = bwd[::-1] + [start] + fwd
            if len(idx) < 2:
                continue
            closed = len(idx) > 3 and np.linalg.norm(P[idx[0]] - P[idx[-1]]) < link
            out.append(make(kind, P[idx], N[idx], bool(closed)))
    return out


def _merge_close(P, N, r):
    keep = np.ones(len(P), bool)
    for i in range(len(P)):
        if keep[i]:
            d = np.linalg.norm(P[i + 1:] - P[i], axis=1)
            keep[i + 1:][d < r] = False
    return P[keep], N[keep]


def _walk(P, used, seed, link, reverse_seed=False):
    """Extend from seed[-1] (or, reversed, away from seed[1]) until no point continues."""
    chain = []
    cur = seed[0]
    prev = None
    if reverse_seed and len(seed) > 1:
        prev = seed[1]
    elif not reverse_seed and len(seed) > 1:
        prev = seed[-2]
    while True:
        free = np.flatnonzero(~used)
        if len(free) == 0:
            break
        d = np.linalg.norm(P[free] - P[cur], axis=1)
        ok = d < link
        if prev is not None:
            direction = P[cur] - P[prev]
            ok &= (P[free] - P[cur]) @ direction > 0
        if not ok.any():
            break
        j = int(free[ok][np.argmin(d[ok])])
        used[j] = True
        chain.append(j)
        prev, cur = cur, j
    return chain
