"""Hatching maps: nested sets of evenly spaced lines fixed on the model (Praun et al.
2001's tonal art maps, laid on the surface), each line the path of a smarticle along the
smoothed cross field (strokes.cross_field), from which a frame draws its hatching
(strokes.hatching.draw): every line of the levels its tone needs, the newest level
thinner as it comes in. The lines do not depend on the light or the eye, so hatching
stays put on a model seen in frame after frame; a model that changes makes its own.

Level 0's lines stand COARSEST line widths apart, each later level's half as far, down
to LEVELS levels; a level's lines are evenly spaced on the surface (Jobard and Lefer
1997): seeded (level 0 at the model's marks, coarse ones first; the others beside the
lines before, a spacing to either side of every other step), a seed taken only where
no line comes within CLEAR of its level's spacing, grown both ways until it comes
within TEST of it of another line, and the lines of one generation taken in order, each
cut where it comes too close to one taken before it. Lines that end facing each other
across such a gap, in line, are then joined (strokes.hatch_join).
"""
from dataclasses import dataclass

import numpy as np

from . import smarticles as sm
from ..blackboard.cells import PointHash, pairs_within
from ..model import keyed
from ..model.projection import project
from ..model.tolerances import NEAR_SURFACE, on_surface
from ..model.vectors import tangents
from .hatch_join import join
from .layers import spawn_flocks

COARSEST = 10.0         # line widths between level 0's lines
LEVELS = 3              # levels at most, each twice as dense as the one before
TEST = 0.6              # a growing line stops this share of its level's spacing from another line
CLEAR = 0.9             # a seed is taken where no line comes within this share of its level's spacing
SIDE = 1.0              # seeds stand this many spacings beside a line ...
SEED_EVERY = 2          # ... at every this many of its steps
GENERATIONS = 2         # rounds of seeds beside the lines of a level, at most
MOST_POINTS = 60_000   # a map of this many points takes no more lines (its finer levels are left sparser)
SHORTEST_LINE = 6       # points: a map's line cut shorter is not kept (a scrap, not a line)
TAKE_BLOCK = 64         # a generation's lines are taken this many at a time, each block tested against the
                        # kept points of the lines taken before it and against its own lines
BEND = np.cos(np.radians(45.0))     # a line ends where it would turn more than this in a step (a knot of the field)
WRAP = np.radians(85.0)     # a line ends where its normal has turned this far from its seed's (round a tube)
FLOCK_APART = 0.5       # flocks' seeds stand half a spacing times the flock size to this power apart: flocks
                        # overlap (their lines cut where they meet) so that a small part still gets one
AGREE = 0.3             # lines whose normals' cosine is below this are on other sheets: never too close
BESIDE = 0.6            # steps: a neighbour's point is beside a point within this far along the point's line
SPREAD_REACH = 2.0       # a line's neighbours are looked for this many of its set's spacings to either side (a side
                        # with none counts as that far)
ONTO = 3                # Newton steps that put a seed beside a line onto the surface
SIDE_SALT = 10          # the keys of the seeds beside a line (a salt, model.keyed)
STEPS_OFF = 1 << 20     # (a step from a line's seed, which may be negative, made a key's whole number)


@dataclass
class HatchMap:
    """The lines, their points one after the other: ``points``, ``normals``, each point's
    ``line``; per line its ``level``, ``key`` (model.keyed: its seed's) and ``start``
    (its first point's row); ``spacing`` (level 0's, in model units) and how many
    ``levels`` there are."""
    points: np.ndarray
    normals: np.ndarray
    line: np.ndarray
    level: np.ndarray
    key: np.ndarray
    start: np.ndarray
    spacing: float
    levels: int = LEVELS
    spread: np.ndarray = None

    def __post_init__(self):
        if self.spread is None:
            self.spread = spread(self)

    def __len__(self):
        return len(self.level)

    def sizes(self):
        return np.diff(np.append(self.start, len(self.points)))


def spread(hmap):
    """How far apart the lines of each set of levels 0..m really stand about each point
    of the map's lines, over how far apart they are meant to (spacing / 2^m): (points,
    levels), the mean of the distances, square to the line, of the nearest line of the
    set on either side (at most SPREAD_REACH spacings; 1 for a set without the point's
    line). Evenly spaced lines (Jobard and Lefer 1997) still stand between TEST and
    about twice their spacing apart; a line drawn as wide as its strip asks keeps the
    tone even (strokes.hatching.widths)."""
    n = len(hmap.points)
    out = np.ones((n, hmap.levels))
    if n == 0:
        return out
    sizes = hmap.sizes()
    P, N = hmap.points, hmap.normals
    T = tangents(P, hmap.start, sizes)
    S = np.cross(N, T)
    line = np.repeat(np.arange(len(sizes)), sizes)
    level = hmap.level[line]
    step = np.linalg.norm(P[1:] - P[:-1], axis=1)
    step = float(np.median(step[line[1:] == line[:-1]])) if n > 1 else 0.0
    for m in range(hmap.levels):
        d = hmap.spacing / 2 ** m
        reach = SPREAD_REACH * d
        rows = np.flatnonzero(level <= m)
        i, j = pairs_within(P[rows], P[rows], reach)
        i, j = rows[i], rows[j]
        dp = P[j] - P[i]
        along = np.einsum("ij,ij->i", dp, T[i])
        keep = (line[i] != line[j]) & (np.einsum("ij,ij->i", N[i], N[j]) > AGREE) & (np.abs(along) <= BESIDE * step)
        i, dp = i[keep], dp[keep]
        across = np.einsum("ij,ij->i", dp, S[i])
        left, right = np.full(n, reach), np.full(n, reach)
        np.minimum.at(left, i[across > 0], across[across > 0])
        np.minimum.at(right, i[across < 0], -across[across < 0])
        out[rows, m] = 0.5 * (left[rows] + right[rows]) / d
    return out


def levels_for(darkest):
    """How many levels a layer needs whose darkest tone covers ``darkest`` of the paper:
    the last is the first at which its lines, at the widest, cover it (darker tones
    widen them)."""
    return int(np.clip(np.ceil(np.log2(max(darkest * COARSEST, 1.0))), 1, LEVELS))


def build(ev, marks, order, flow, heads, step, steps, weights, width, rules=None, flock_size=1, levels=LEVELS,
          within=None):
    """The hatching map of a model: its ``marks`` (in ``order``, lower first) seed level 0;
    smarticles follow ``flow`` (a strokes.smarticles direction field), setting off as
    ``heads(points, normals, reference directions)`` says, ``steps`` each way of ``step``
    at most, with ``weights`` and flocks of ``flock_size``; ``width``: the widest line
    (model units), whose COARSEST times is level 0's spacing; ``rules``: more termination
    rules (strokes.smarticles.StrokeRules: the sign of the curvature); ``levels``: how
    many (:func:`levels_for`); ``within``: which points may seed a line (a function of
    points; default all: the style's convex or concave parts)."""
    spacing = COARSEST * width
    acc = _Accepted()
    P, N, keys = marks.points, marks.normals, marks.keys
    H = heads(P, N, marks.ref)
    rank = np.argsort(np.argsort(np.asarray(order), kind="stable"), kind="stable")
    for level in range(levels):
        d = spacing / 2 ** level
        if level and acc.points() > MOST_POINTS:
            break
        if level:
            P, N, H, keys, rank = _beside(ev, acc, range(len(acc.lines)), d, level, within)
        for _ in range(GENERATIONS):
            if len(P) == 0 or acc.points() > MOST_POINTS:      # (a model stretched out of all measure)
                break
            new = _generation(ev, acc, P, N, H, keys, rank, d, level, flow, step, steps, weights, rules,
                              flock_size)
            P, N, H, keys, rank = _beside(ev, acc, new, d, level, within)
    return _map(join(ev, [(p, n, lv, key) for p, n, lv, key, _ in acc.lines], spacing, step), spacing, levels)


class _Accepted:
    """The lines taken so far, and their points (with normals) for the nearness tests."""

    def __init__(self):
        self.lines = []                    # (points, normals, level, key, rel)
        self._P, self._N = [np.zeros((0, 3))], [np.zeros((0, 3))]

    def add(self, points, normals, level, key, rel):
        self.lines.append((points, normals, level, key, rel))
        self._P.append(points)
        self._N.append(normals)

    def points(self):
        return sum(len(p) for p in self._P)

    @property
    def P(self):
        if len(self._P) > 1:
            self._P = [np.concatenate(self._P)]
        return self._P[0]

    @property
    def N(self):
        if len(self._N) > 1:
            self._N = [np.concatenate(self._N)]
        return self._N[0]

    def near(self, X, Nx, r):
        """Which points X (with normals Nx) have a taken point of their sheet within r."""
        out = np.zeros(len(X), bool)
        if len(self.P) and len(X):
            i, j = pairs_within(X, self.P, r)
            out[i[np.einsum("ij,ij->i", Nx[i], self.N[j]) > AGREE]] = True
        return out



def _map(lines, spacing, levels):
    """The HatchMap of lines (points, normals, level, key), in order of their level, then
    longest first, then key (the order a frame's hatching gives way in where line ends
    crowd, strokes.hatching.spread_ends: parts of the map cut one sequence)."""
    lines = [lines[k] for k in sorted(range(len(lines)), key=lambda k: (lines[k][2], -len(lines[k][0]),
                                                                         int(lines[k][3])))]
    if not lines:
        z = np.zeros((0, 3))
        return HatchMap(z, z, np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros(0, np.uint64),
                        np.zeros(0, np.int64), spacing, levels)
    sizes = np.array([len(p) for p, *_ in lines])
    return HatchMap(np.concatenate([p for p, *_ in lines]), np.concatenate([n for _, n, *_ in lines]),
                    np.repeat(np.arange(len(sizes)), sizes), np.array([lv for _, _, lv, _ in lines]),
                    np.array([k for *_, k in lines], np.uint64), np.cumsum(sizes) - sizes, spacing, levels)


def _generation(ev, acc, P, N, H, keys, rank, d, level, flow, step, steps, weights, rules, flock_size):
    """One generation of a level: its seeds (in ``rank`` order) clear of the lines taken,
    kept ``d`` apart, grown both ways, taken in order and cut where they come within
    TEST d of a line taken before them. Returns the numbers of the lines taken."""
    from .stipples import spaced
    clear = ~acc.near(P, N, CLEAR * d)
    ok = np.flatnonzero(clear)
    ok = ok[spaced(P[ok], np.full(len(ok), 0.5 * d * flock_size ** FLOCK_APART), keys[ok], first=rank[ok])]
    if len(ok) == 0:
        return []
    ok = ok[np.argsort(rank[ok], kind="stable")]
    P, N, H, keys = P[ok], N[ok], H[ok], keys[ok]
    flock = np.arange(len(P))
    if flock_size > 1:                 # each seed a flock, side by side across its heading (Smarticles 4)
        P, H, flock, keys = spawn_flocks(P, N, H, flock_size, d, keys)
    n = len(P)
    taken = PointHash(acc.P, TEST * d)
    M = acc.N.copy()
    last = np.zeros((2 * n, 3))                        # each smarticle's last step

    def stop(ids, before, after, normals):
        ends = np.zeros(len(after), bool)
        i, j = taken.pairs(after)
        ends[i[np.einsum("ij,ij->i", normals[i], M[j]) > AGREE]] = True
        step_ = after - before
        prev = last[ids]
        ends |= np.einsum("ij,ij->i", step_, prev) < BEND * np.linalg.norm(step_, axis=1) * np.linalg.norm(prev, axis=1)
        last[ids] = step_
        return ends, None
    base = rules or sm.StrokeRules()
    run_rules = sm.StrokeRules(max_steps=steps, max_normal_angle=WRAP,
                               stop_on_curvature_sign=base.stop_on_curvature_sign, stop=stop)
    both = sm.both_ways(ev, P, H, keys, flow, step, weights, run_rules, flock=flock,
                        separation_radius=d)                             # (a flock keeps its spacing)
    return _take(acc, [(pts, nrm, seed, keys[k]) for k, pts, nrm, _, seed in both], d, level)


def _take(acc, lines, d, level):
    """The lines of a generation taken in order (:func:`_generation`): each cut where it
    comes within TEST ``d`` of a line taken before it, dropped where its seed does. The
    lines are looked at TAKE_BLOCK at a time, against the kept points of the lines taken
    so far and the block's own."""
    if not lines:
        return []
    sizes = np.array([len(p) for p, _, _, _ in lines])
    first = np.cumsum(sizes) - sizes
    seed = np.array([s for _, _, s, _ in lines])
    P = np.concatenate([p for p, _, _, _ in lines])
    N = np.concatenate([n for _, n, _, _ in lines])
    owner = np.repeat(np.arange(len(lines)), sizes)
    local = np.arange(len(owner)) - first[owner]
    lo, hi = np.zeros(len(lines), np.int64), sizes.copy()
    taken = np.zeros(len(lines), bool)
    kept = np.zeros(0, np.int64)                         # rows of the taken lines' kept points
    out = []
    for b0 in range(0, len(lines), TAKE_BLOCK):
        b1 = min(b0 + TAKE_BLOCK, len(lines))
        rows = np.arange(first[b0], first[b1 - 1] + sizes[b1 - 1])
        others = np.concatenate([kept, rows])
        i, j = pairs_within(P[rows], P[others], TEST * d)
        i, j = rows[i], others[j]
        keep = (owner[i] > owner[j]) & (np.einsum("ij,ij->i", N[i], N[j]) > AGREE)
        i, j = i[keep], j[keep]
        starts = np.searchsorted(owner[i], np.arange(b0, b1 + 1))
        for k in range(b0, b1):
            a, b = i[starts[k - b0]:starts[k - b0 + 1]], j[starts[k - b0]:starts[k - b0 + 1]]
            alive = taken[owner[b]] & (local[b] >= lo[owner[b]]) & (local[b] < hi[owner[b]])
            pos = local[a[alive]]
            if (pos == seed[k]).any():
                hi[k] = 0
                continue
            ahead, behind = pos[pos > seed[k]], pos[pos < seed[k]]
            hi[k] = ahead.min() if len(ahead) else hi[k]
            lo[k] = behind.max() + 1 if len(behind) else 0
            taken[k] = hi[k] - lo[k] >= SHORTEST_LINE
            if taken[k]:
                p, n, s, key = lines[k]
                acc.add(p[lo[k]:hi[k]], n[lo[k]:hi[k]], level, key, np.arange(lo[k], hi[k]) - s)
                out.append(len(acc.lines) - 1)
        done = np.arange(b0, b1)[taken[b0:b1]]
        if len(done):
            kept = np.concatenate([kept] + [np.arange(first[k] + lo[k], first[k] + hi[k]) for k in done])
    return out


def _beside(ev, acc, which, d, level, within=None):
    """Seeds beside the taken lines ``which`` (their numbers): at every SEED_EVERY-th step
    of each from its seed, SIDE ``d`` to either side on the surface, heading along the
    line; their keys from the line's, the step and the side; their order the lines' and
    then along them."""
    rows = []
    for w in which:
        p, n, _, key, rel = acc.lines[w]
        k = np.arange(1, len(p) - 1)
        k = k[rel[k] % SEED_EVERY == 0]
        if len(k):
            rows.append((p, n, key, rel, k))
    empty = (np.zeros((0, 3)),) * 3 + (np.zeros(0, np.uint64), np.zeros(0, np.int64))
    if not rows:
        return empty
    P = np.concatenate([p[k] for p, _, _, _, k in rows])
    N = np.concatenate([n[k] for _, n, _, _, k in rows])
    T = np.concatenate([p[k + 1] - p[k - 1] for p, _, _, _, k in rows])
    base = np.concatenate([keyed.combine(np.full(len(k), key, np.uint64), (rel[k] + STEPS_OFF).astype(np.int64))
                           for _, _, key, rel, k in rows])
    T = T - np.einsum("ij,ij->i", T, N)[:, None] * N
    T /= np.maximum(np.linalg.norm(T, axis=1, keepdims=True), 1e-300)
    S = np.cross(N, T)
    X, f, g = project(ev, np.concatenate([P + SIDE * d * S, P - SIDE * d * S]), ONTO)
    keys = keyed.combine(np.concatenate([base, base]), np.repeat([1, 2], len(P)).astype(np.uint64), level,
                         SIDE_SALT)
    ok = on_surface(f, ev.iso, NEAR_SURFACE)
    if within is not None and ok.any():
        ok[ok] = within(X[ok])
    X, g, keys = X[ok], g[ok], keys[ok]
    Nx = -g / np.maximum(np.linalg.norm(g, axis=1, keepdims=True), 1e-300)
    H = np.concatenate([T, T])[ok]
    H = H - np.einsum("ij,ij->i", H, Nx)[:, None] * Nx
    H /= np.maximum(np.linalg.norm(H, axis=1, keepdims=True), 1e-300)
    return X, Nx, H, keys, np.arange(len(X))
