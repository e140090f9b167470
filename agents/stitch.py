"""Join the points traced by different agents into whole polylines.

Agents trace one curve from several seeds at once and stop where they meet another's
trace, so a curve arrives in pieces that meet head to head, sometimes overlapping by a
step. All points of one kind are pooled (points sharing a cell an eighth of a link wide
are merged), and polylines are chained greedily through a spatial hash: from a chain's
end to the nearest unused point within ``link`` that continues forward (positive dot
product with the current direction), then the same from the chain's other end. A chain
whose ends meet is closed.
"""
import numpy as np

from ..blackboard.keys import unique_rows

_OFFSETS = [(dx, dy, dz) for dx in (-1, 0, 1) for dy in (-1, 0, 1) for dz in (-1, 0, 1)]


def stitch(outlines, link, make):
    out = []
    outlines = [o for o in outlines if len(o.points)]
    for kind in sorted({o.kind for o in outlines}):
        mine = [o for o in outlines if o.kind == kind]
        P = np.concatenate([o.points for o in mine])
        N = np.concatenate([o.normals for o in mine])
        P, N = _merge_close(P, N, link / 8.0)
        grid = _Grid(P, link)
        used = np.zeros(len(P), bool)
        for start in range(len(P)):
            if used[start]:
                continue
            used[start] = True
            grid.remove(start)
            fwd = _walk(P, grid, used, start, None, link)
            bwd = _walk(P, grid, used, start, fwd[0] if fwd else None, link, away=True)
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


class _Grid:
    def __init__(self, P, cell):
        self.cell = cell
        self.cells = {}
        keys = np.floor(P / cell).astype(np.int64)
        self.keys = [tuple(k) for k in keys.tolist()]
        for i, k in enumerate(self.keys):
            self.cells.setdefault(k, set()).add(i)

    def remove(self, i):
        self.cells[self.keys[i]].discard(i)

    def near(self, i):
        x, y, z = self.keys[i]
        out = []
        for dx, dy, dz in _OFFSETS:
            s = self.cells.get((x + dx, y + dy, z + dz))
            if s:
                out.extend(s)
        return out


def _walk(P, grid, used, start, neighbour, link, away=False):
    """Extend a chain from ``start``; with ``away``, leave in the direction opposite to
    ``neighbour`` (the chain's other side)."""
    chain = []
    cur = start
    prev = neighbour if away else None
    while True:
        cand = grid.near(cur)
        if not cand:
            break
        cand = np.array(cand)
        d = np.linalg.norm(P[cand] - P[cur], axis=1)
        ok = d < link
        if prev is not None:
            ok &= (P[cand] - P[cur]) @ (P[cur] - P[prev]) > 0
        if not ok.any():
            break
        j = int(cand[ok][np.argmin(d[ok])])
        used[j] = True
        grid.remove(j)
        chain.append(j)
        prev, cur = cur, j
    return chain
