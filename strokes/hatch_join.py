"""Joining a hatching map's lines that meet end to end (strokes.hatch_map): lines grown
at the same time from seeds along one track stop where they come within the test
distance of each other (Jobard and Lefer 1997), so one track is drawn as dashes with a
gap at every meeting. Where two lines of a level end facing each other across such a
gap, nearly in line and on one sheet, with no other line in between, they are one line:
the gap is bridged on the surface and the line runs on, as an engraver's would."""
import numpy as np

from ..blackboard.cells import PointHash, pairs_within
from ..model.projection import project
from ..model.tolerances import NEAR_SURFACE, on_surface

JOIN = 2.0              # of its level's spacing: the widest gap between two ends that join ...
IN_LINE = np.cos(np.radians(40.0))  # ... each end's direction this close to the way across the gap ...
ASIDE = 0.3             # ... and the other end no further than this share of the spacing to either side of it
CLEARANCE = 0.3         # of the level's spacing: no other line comes nearer the bridge than this
SHEET = 0.9             # the cosine of the normals at two ends on one sheet, at least
SMOOTH_POINTS = 4       # points of each line either side of a join eased over to the other ...
SMOOTH_TIMES = 6        # ... by this many rounds of averaging with their neighbours
ONTO = 3                # Newton steps that put a bridge's points onto the surface


def join(ev, lines, spacing, step):
    """The lines (points, normals, level, key) with those that meet end to end joined
    (greedily, the narrowest gap first; no line joins itself into a ring); a joined
    line keeps the key of its longest part."""
    if len(lines) < 2:
        return list(lines)
    ends = _ends(lines)
    edges = _edges(ev, lines, ends, spacing, step)
    if not edges:
        return list(lines)
    return _chains(ev, lines, edges)


def _ends(lines):
    """Per end (line k's head 2k, tail 2k + 1): its point, outward direction, normal."""
    P, T, N = [], [], []
    for p, n, *_ in lines:
        for at, inner in ((0, 1), (-1, -2)):
            t = p[at] - p[inner] if len(p) > 1 else np.zeros(3)
            P.append(p[at])
            T.append(t / max(np.linalg.norm(t), 1e-300))
            N.append(n[at])
    return np.array(P), np.array(T), np.array(N)


def _edges(ev, lines, ends, spacing, step):
    """The joins taken: (end, end, bridge points, bridge normals), narrowest gap first."""
    E, T, N = ends
    level = np.repeat([lv for _, _, lv, _ in lines], 2)
    reach = JOIN * spacing / 2.0 ** level
    i, j = pairs_within(E, E, float(reach.max()))
    g = E[j] - E[i]
    dist = np.linalg.norm(g, axis=1)
    ahead_i, ahead_j = np.einsum("ij,ij->i", T[i], g), -np.einsum("ij,ij->i", T[j], g)
    aside = ASIDE * reach[i] / JOIN
    ok = (i < j) & (i // 2 != j // 2) & (level[i] == level[j]) & (dist < reach[i]) & (dist > 0) & \
         (ahead_i > IN_LINE * dist) & (ahead_j > IN_LINE * dist) & (np.einsum("ij,ij->i", N[i], N[j]) > SHEET) & \
         (dist ** 2 - ahead_i ** 2 < aside ** 2) & (dist ** 2 - ahead_j ** 2 < aside ** 2)
    i, j, dist = i[ok], j[ok], dist[ok]
    if len(i) == 0:
        return []
    order = np.argsort(dist, kind="stable")
    owner = np.repeat(np.arange(len(lines)), [len(p) for p, *_ in lines])
    hashes = {}                                     # per level, every line's points hashed at its clearance

    def crossed(a, b, X, lv):
        """Whether a line other than a's and b's comes within the clearance of the gap:
        of the bridge's points and of the chord, sampled at least that finely."""
        r = CLEARANCE * spacing / 2.0 ** lv
        if lv not in hashes:
            hashes[lv] = PointHash(np.concatenate([p for p, *_ in lines]), r)
        k = int(np.ceil(np.linalg.norm(E[b] - E[a]) / r)) + 1
        chord = E[a] + np.linspace(0.0, 1.0, k + 1)[1:-1, None] * (E[b] - E[a])
        _, near = hashes[lv].pairs(np.vstack([X, chord]))
        return np.isin(owner[near], (a // 2, b // 2), invert=True).any()

    root = list(range(len(lines)))

    def find(a):
        while root[a] != a:
            root[a] = root[root[a]]
            a = root[a]
        return a

    i, j = i[order], j[order]
    bridges = _bridges(ev, E[i], E[j], step)
    used = np.zeros(len(E), bool)
    out = []
    for k in range(len(i)):
        a, b = int(i[k]), int(j[k])
        if used[a] or used[b] or find(a // 2) == find(b // 2) or bridges[k] is None:
            continue
        X, Nx = bridges[k]
        if crossed(a, b, X, level[a]):
            continue
        used[a] = used[b] = True
        root[find(a // 2)] = find(b // 2)
        out.append((a, b, X, Nx))
    return out


def _bridges(ev, A, B, step):
    """Per gap from A to B: points on the surface between its ends, about ``step`` apart
    (none for a gap of one step), and their normals; None where they do not reach the
    surface. All gaps' points are put onto it together."""
    k = np.ceil(np.linalg.norm(B - A, axis=1) / step).astype(np.int64)
    inner = np.where(k < 2, 0, k - 1)                     # points inside each gap
    gap = np.repeat(np.arange(len(A)), inner)
    s = (np.arange(len(gap)) - np.repeat(np.cumsum(inner) - inner, inner) + 1) / k[gap]
    X, f, g = project(ev, A[gap] + s[:, None] * (B - A)[gap], ONTO)
    Nx = -g / np.maximum(np.linalg.norm(g, axis=1, keepdims=True), 1e-300)
    off = np.bincount(gap[~on_surface(f, ev.iso, NEAR_SURFACE)], minlength=len(A))
    at = np.cumsum(inner) - inner
    return [None if off[q] else (X[at[q]:at[q] + inner[q]], Nx[at[q]:at[q] + inner[q]]) for q in range(len(A))]


def _chains(ev, lines, edges):
    """The lines joined along the edges into chains, each walked from a free end, and
    eased about each join (:func:`_smoothed`)."""
    link = {}
    for a, b, X, Nx in edges:
        link[a] = (b, X, Nx)
        link[b] = (a, X[::-1], Nx[::-1])
    seen = np.zeros(len(lines), bool)
    out = []
    for k in range(len(lines)):
        if seen[k] or (2 * k in link and 2 * k + 1 in link):
            continue                       # (a chain is walked from a line with a free end)
        forward = 2 * k not in link          # leave by the tail, or (its head linked) by the head, reversed
        parts, line = [], k
        while True:
            seen[line] = True
            p, n, lv, key = lines[line]
            parts.append((p if forward else p[::-1], n if forward else n[::-1], len(p), key))
            leave = 2 * line + 1 if forward else 2 * line
            if leave not in link:
                break
            other, X, Nx = link[leave]
            parts.append((X, Nx, 0, None))
            line, forward = other // 2, other % 2 == 0
        key = max((m, key) for _, _, m, key in parts if key is not None)[1]
        P, N = np.concatenate([p for p, _, _, _ in parts]), np.concatenate([n for _, n, _, _ in parts])
        at = np.cumsum([len(p) for p, _, _, _ in parts])
        joins = [(at[i - 1] - 1, at[i]) for i in range(1, len(parts), 2)]     # each bridge's ends' rows
        out.append((P, N, joins, lines[k][2], key))
    return _smoothed(ev, out)


def _smoothed(ev, chains):
    """The joined lines (points, normals, joins, level, key) as lines, their points (and
    normals) eased about each join: SMOOTH_POINTS either side of the bridge averaged
    with their neighbours SMOOTH_TIMES, put back onto the surface (all lines' together),
    so that a line meeting one a little to its side bends over to it instead of
    stepping across."""
    eased = []
    for P, N, joins, _, _ in chains:
        if not joins:
            eased.append(np.zeros(0, np.int64))
            continue
        rows = np.unique(np.concatenate([np.arange(max(a - SMOOTH_POINTS + 1, 1), min(b + SMOOTH_POINTS, len(P) - 1))
                                         for a, b in joins]))
        eased.append(rows)
    S = []
    for (P, _, _, _, _), rows in zip(chains, eased):
        Q = P.copy()
        for _ in range(SMOOTH_TIMES):
            Q[rows] = 0.25 * Q[rows - 1] + 0.5 * Q[rows] + 0.25 * Q[rows + 1]
        S.append(Q[rows])
    X, f, g = project(ev, np.concatenate(S) if S else np.zeros((0, 3)), ONTO)
    ok = on_surface(f, ev.iso, NEAR_SURFACE)                 # (a point that does not reach it stays as it was)
    Nx = -g / np.maximum(np.linalg.norm(g, axis=1, keepdims=True), 1e-300)
    out, at = [], 0
    for (P, N, _, level, key), rows in zip(chains, eased):
        here = slice(at, at + len(rows))
        at += len(rows)
        if len(rows):
            P, N = P.copy(), N.copy()
            P[rows[ok[here]]] = X[here][ok[here]]
            N[rows[ok[here]]] = Nx[here][ok[here]]
        out.append((P, N, level, key))
    return out
