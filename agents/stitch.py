"""Join the points traced by different agents into whole polylines.

Agents trace one curve from several seeds at once and stop where they meet another's
trace, so a curve arrives in pieces that meet head to head, sometimes overlapping by a
step. All points of one kind are pooled (points sharing a cell an eighth of a link wide
are merged), and polylines are chained greedily: each point's neighbours within
``link`` are found once, nearest first (the lower-numbered on an exact tie), and a chain
goes from its end to the nearest unused one that continues forward (positive dot
product with the current direction), then the same from the chain's other end. A chain
whose ends meet is closed.
"""
import numpy as np

from ..blackboard.board import pairs_within
from ..blackboard.keys import unique_rows


def stitch(outlines, link, make):
    out = []
    outlines = [o for o in outlines if len(o.points)]
    for kind in sorted({o.kind for o in outlines}):
        mine = [o for o in outlines if o.kind == kind]
        P = np.concatenate([o.points for o in mine])
        N = np.concatenate([o.normals for o in mine])
        P, N = _merge_close(P, N, link / 8.0)
        near = _Near(P, link)
        used = [False] * len(P)
        for start in range(len(P)):
            if used[start]:
                continue
            used[start] = True
            fwd = near.walk(used, start, None)
            bwd = near.walk(used, start, fwd[0] if fwd else None)
            idx = bwd[::-1] + [start] + fwd
            if len(idx) < 2:
                continue
            closed = len(idx) > 3 and np.linalg.norm(P[idx[0]] - P[idx[-1]]) < link
            out.append(make(kind, P[idx], N[idx], bool(closed)))
    return out


def _merge_close(P, N, r):
    """Keep the first point of each cell of size r (order preserved)."""
    keys = np.floor(P / r).astype(np.int64)
    _, first = unique_rows(keys, return_index=True)
    keep = np.sort(first)
    return P[keep], N[keep]


class _Near:
    """Each point's neighbours closer than ``link``, nearest first (found in one batch)."""

    def __init__(self, P, link):
        i, j = pairs_within(P, P, link)
        other = i != j
        i, j = i[other], j[other]
        d2 = ((P[i] - P[j]) ** 2).sum(axis=1)
        order = np.lexsort((j, d2, i))
        self.nbrs = j[order].tolist()
        self.first = np.searchsorted(i[order], np.arange(len(P) + 1)).tolist()
        self.P = P.tolist()

    def walk(self, used, start, neighbour):
        """Extend a chain from ``start`` (``used`` points are not taken; the points taken
        become used): each time to the nearest unused neighbour, ahead of the way the
        chain came (given ``neighbour``, the chain's other side: away from it)."""
        P, nbrs, first = self.P, self.nbrs, self.first
        chain = []
        cur, prev = start, neighbour
        while True:
            x, y, z = P[cur]
            nxt = None
            if prev is None:
                for k in range(first[cur], first[cur + 1]):
                    if not used[nbrs[k]]:
                        nxt = nbrs[k]
                        break
            else:
                px, py, pz = P[prev]
                dx, dy, dz = x - px, y - py, z - pz
                for k in range(first[cur], first[cur + 1]):
                    j = nbrs[k]
                    if not used[j]:
                        q = P[j]
                        if (q[0] - x) * dx + (q[1] - y) * dy + (q[2] - z) * dz > 0:
                            nxt = j
                            break
            if nxt is None:
                return chain
            used[nxt] = True
            chain.append(nxt)
            prev, cur = cur, nxt
