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

from ..blackboard.cells import pairs_within
from ..blackboard.keys import unique_rows
from ..model.vectors import tangents

REACH = 1.6         # ends pointing at each other are joined across up to this many links
AHEAD = 0.8         # ... each end's direction within about 37 degrees of the gap's
SAME_SHEET = 0.95   # ... and their normals within about 18 degrees
HEADING = 0.5       # an end reaches into another line heading across it (30 degrees at least) ...
LATERAL = 0.25      # ... or lying on its run (within about 14 degrees of its tangent there)


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
        chains = []
        for start in range(len(P)):
            if used[start]:
                continue
            used[start] = True
            fwd = near.walk(used, start, None)
            bwd = near.walk(used, start, fwd[0] if fwd else None)
            idx = bwd[::-1] + [start] + fwd
            if len(idx) >= 2:
                chains.append(idx)
        for idx, closed in join_ends(P, N, chains, link):
            out.append(make(kind, P[idx], N[idx], bool(closed)))
    return out


def join_ends(P, N, chains, link, reach=True, same_sheet=SAME_SHEET, group=None, apart=None, ahead=AHEAD):
    """Chains (index lists into P) whose ends face each other across a gap a little
    wider than ``link`` (at most REACH times it; per point of P, or one for all: two
    ends take the wider of theirs), nearest pair first, joined into one:
    each end's own direction points across the gap to the other end (within AHEAD), and
    the normals there agree (within ``same_sheet``); a chain of more than three points
    whose own ends face each other so closes. Two traces of one curve stop where each
    meets the other, sometimes a few steps short; a gap this narrow between ends that
    point at each other is that curve's, not a junction's. Returns (indices, closed)
    per joined chain (closed: its own two ends within ``link``, or pieces joined round);
    with ``reach``, a free end's reach (:func:`_reach_across`: True, REACH of its link;
    or a distance per point of P; ``ahead`` of its direction) extends ``chains``' lists
    in place. Given ``group`` (per point of P), only ends of different groups join, and
    an end reaches only another group's points; given ``apart`` (a link per point of
    P), two ends join across REACH of the wider of theirs instead (a chain still closes
    on itself within ``link``)."""
    link = np.broadcast_to(np.asarray(link, float), (len(P),))
    apart = link if apart is None else np.broadcast_to(np.asarray(apart, float), (len(P),))
    ends = [(c, e) for c, idx in enumerate(chains) for e in (0, 1) if not _closed(P, idx, link)]
    partner = {}
    if len(ends) >= 2:
        tip = np.array([chains[c][0] if e == 0 else chains[c][-1] for c, e in ends])
        back = np.array([chains[c][1] if e == 0 else chains[c][-2] for c, e in ends])
        out_dir = P[tip] - P[back]
        out_dir /= np.maximum(np.linalg.norm(out_dir, axis=1, keepdims=True), 1e-300)
        owner = np.array([c for c, _ in ends])
        loop = np.array([len(chains[c]) > 3 for c, _ in ends])      # may close on itself
        i, j = pairs_within(P[tip], P[tip], REACH * float(apart[tip].max()))
        keep = (i < j) & ((owner[i] != owner[j]) | loop[i])
        if group is not None:
            keep &= group[tip[i]] != group[tip[j]]
        i, j = i[keep], j[keep]
        gap = P[tip[j]] - P[tip[i]]
        dist = np.linalg.norm(gap, axis=1)
        g = gap / np.maximum(dist, 1e-300)[:, None]
        ok = ((dist <= REACH * np.maximum(apart[tip[i]], apart[tip[j]]))
              & (np.einsum("ij,ij->i", out_dir[i], g) >= AHEAD) & (np.einsum("ij,ij->i", out_dir[j], -g) >= AHEAD)
              & (np.einsum("ij,ij->i", N[tip[i]], N[tip[j]]) >= same_sheet))
        for k in np.flatnonzero(ok)[np.argsort(dist[ok], kind="stable")].tolist():
            x, y = ends[i[k]], ends[j[k]]
            if x not in partner and y not in partner:
                partner[x], partner[y] = y, x
    reached = set()
    if reach is not False:
        within = REACH * link if reach is True else np.broadcast_to(np.asarray(reach, float), (len(P),))
        reached = _reach_across(P, N, chains, [x for x in ends if x not in partner], within, same_sheet, ahead,
                                group)
    out, seen = [], set()

    def walk(c, e):
        """The chain c entered at its end e, and those joined on beyond its other end."""
        idx, closed = [], False
        while c not in seen:
            seen.add(c)
            idx += chains[c] if e == 0 else chains[c][::-1]
            nxt = partner.get((c, 1 - e))
            if nxt is None:
                break
            c, e = nxt
            closed = c in seen
        return idx, closed, (c, 1 - e)

    for c in range(len(chains)):                    # pieces with a free end first, from that end
        for e in (0, 1):
            if c not in seen and (c, e) not in partner:
                idx, _, last = walk(c, e)
                # (an end run on to another line ends there: not closed on itself)
                out.append((idx, _closed(P, idx, link) and (c, e) not in reached and last not in reached))
    for c in range(len(chains)):                    # what is left: pieces joined round
        if c not in seen:
            out.append(walk(c, 0)[:2])
    return out


def _closed(P, idx, link):
    """Whether a chain's ends meet (within the wider ``link`` of its ends' points; it has
    more than three points)."""
    return len(idx) > 3 and np.linalg.norm(P[idx[0]] - P[idx[-1]]) < max(link[idx[0]], link[idx[-1]])


def _reach_across(P, N, chains, free, within, same_sheet=SAME_SHEET, ahead=AHEAD, group=None):
    """Free ends (chain, 0 start / 1 end) reach the nearest point of another chain that
    lies ahead of them (within ``within`` of the end, per point of P, and ``ahead`` of
    its direction) on the same sheet (``same_sheet``; given ``group``, of another
    group), if the end heads across that line there (HEADING, of the gap's part across
    the line's tangent) or lies on its run (that part within LATERAL of the gap), not
    beside a line running alongside: it becomes their chain's last point (of two ends
    that run on to each other's chains, the first only). Returns the ends so extended.
    A trace stops short where it meets another outline, and where it met that one's
    middle (a cusp, a junction) no free point was left there for the chaining to take."""
    if not free or len(chains) < 2:
        return set()
    tip = np.array([chains[c][0] if e == 0 else chains[c][-1] for c, e in free])
    back = np.array([chains[c][1] if e == 0 else chains[c][-2] for c, e in free])
    d = P[tip] - P[back]
    d /= np.maximum(np.linalg.norm(d, axis=1, keepdims=True), 1e-300)
    sizes = np.array([len(idx) for idx in chains])
    every = np.concatenate([np.asarray(idx) for idx in chains])
    owner = np.repeat(np.arange(len(chains)), sizes)
    T = tangents(P[every], np.cumsum(sizes) - sizes, sizes)
    i, j = pairs_within(P[tip], P[every], float(within[tip].max()))
    mine = np.array([c for c, _ in free])
    other = owner[j] != mine[i]
    if group is not None:
        other &= group[every[j]] != group[tip[i]]
    i, j = i[other], j[other]
    gap = P[every[j]] - P[tip[i]]
    dist = np.linalg.norm(gap, axis=1)
    ok = ((dist <= within[tip[i]]) & (np.einsum("ij,ij->i", d[i], gap) >= ahead * dist)
          & (np.einsum("ij,ij->i", N[tip[i]], N[every[j]]) >= same_sheet) & (dist > 0))
    # (not a line running alongside: the end heads across the other line, or lies on its run)
    lat = gap - np.einsum("ij,ij->i", gap, T[j])[:, None] * T[j]
    off = np.linalg.norm(lat, axis=1)
    ok &= (np.einsum("ij,ij->i", d[i], lat) >= HEADING * off) | (off <= LATERAL * dist)
    i, j, dist = i[ok], j[ok], dist[ok]
    order = np.lexsort((dist, i))
    first = np.ones(len(order), bool)
    first[1:] = i[order][1:] != i[order][:-1]
    target = dict(zip(i[order][first].tolist(), every[j[order][first]].tolist()))
    tip_of = {t: k for k, t in enumerate(tip.tolist())}
    reached = set()
    for k, q in target.items():
        c, e = free[k]
        other = tip_of.get(q)
        if other is not None and free[other] in reached and target[other] in chains[c]:
            continue                                # two ends that reach each other: one join
        if e == 0:
            chains[c].insert(0, q)
        else:
            chains[c].append(q)
        reached.add((c, e))
    return reached


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
