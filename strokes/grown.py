"""Lines grown on the paper (Jobard and Lefer 1997): the strokes started from the
feature chains and the short strokes, a frame's own (their seeds depend on the outlines
or are short-lived), spaced by their tone as the eye sees them.

A layer is drawn in generations. The first is its seeds (marks, coarse ones first, or
points on the feature chains); each later one the seeds beside the lines just drawn, a
spacing to either side of every point. A seed closer on the paper to a drawn line than
CLEAR of the spacing its tone asks for (strokes.hatching.spacing) is not taken; the
others set off two smarticles, forwards and backwards, that step until they come
closer to a drawn line than TEST of that spacing, leave the tone that wants this layer,
turn away from the eye, cross a visible outline, or run out of steps (strokes.
smarticles' rules). Lines of one generation are taken in order, each cut where it comes
too close to one taken before it. A line's width follows its tone, its points keep
their seed's key (``Stroke.mark``: a mark's, a side seed's from its line's and step).
"""
import numpy as np

from . import smarticles as sm
from ..model import keyed
from ..model.projection import project
from ..model.tolerances import NEAR_SURFACE, on_surface
from .data import Stroke
from .hatching import SHORTEST, _outline_segments, _turning, width
from .layers import spawn_flocks
from .paper import close_pairs
from .stipples import spaced
from .visibility import piece, run_points, visible, visible_marks

TEST = 0.6              # a growing line stops this share of its spacing from a drawn line
SIDE = 1.05             # seeds stand this many spacings beside a drawn line ...
CLEAR = 0.9             # ... and are taken where no drawn line comes within this share of their spacing
SEED_EVERY = 1          # ... at every this many of its points
SIDE_SALT = 10          # the keys of the seeds beside a line (a salt, model.keyed)
ONTO = 3                # Newton steps that put a seed beside a line onto the surface
STEPS_OFF = 1 << 20     # (a step from a line's seed, which may be negative, made a key's whole number)


def from_marks(layer, marks, order):
    """The layer's lines from a part's marks (in ``order``: lower first) and the seeds
    beside the lines they make, generation after generation, as strokes."""
    H = layer.headings(marks.points, marks.normals, marks.ref)
    return grow(layer, marks.points, marks.normals, H, marks.keys, order)


def grow(layer, P, N, H, keys, order):
    """The layer's lines from seeds (points, normals, headings, keys; in ``order``: lower
    first) that face the eye, want this layer's ink and are seen, and the seeds beside
    the lines they make, generation after generation, as strokes."""
    keep = layer.paper.facing(P, N)
    if layer.rules.region is not None:
        keep &= layer.rules.region.contains(P)
    P, N, H, keys, order = P[keep], N[keep], H[keep], np.asarray(keys)[keep], np.asarray(order)[keep]
    t = layer.tone(P, N)
    keep = np.isfinite(layer.spacing(t))
    P, N, H, keys, order, t = P[keep], N[keep], H[keep], keys[keep], order[keep], t[keep]
    seen = visible(layer.sight, P, layer.paper.eye, N)
    P, N, H, keys, t = P[seen], N[seen], H[seen], keys[seen], t[seen]
    rank = np.argsort(np.argsort(order[seen], kind="stable"), kind="stable")
    out = []
    crossing = _outline_segments(layer)
    while len(P):
        lines, tones = _generation(layer, P, N, H, keys, t, rank, crossing)
        out += lines
        P, N, H, keys, t, rank = _beside(layer, lines, tones)
    return out


def _generation(layer, P, N, H, keys, t, rank, crossing):
    """One generation: its seeds (in ``rank`` order) that keep clear of the lines drawn,
    grown, each cut where it comes too close to one taken before it; returns the
    strokes, their lines added to the layer's drawn ones."""
    Q, scale = layer.paper.place(P)
    d = layer.spacing(t) * scale
    clear = np.ones(len(P), bool)
    if len(layer.drawn.places):
        i, _ = close_pairs(Q, CLEAR * 0.5 * d, layer.drawn.places, CLEAR * layer.drawn.reach)
        clear[i] = False
    ok = np.flatnonzero(clear)
    ok = ok[spaced(Q[ok], 0.5 * d[ok], keys[ok], first=rank[ok])]
    if len(ok) == 0:
        return [], []
    ok = ok[np.argsort(rank[ok], kind="stable")]
    P, N, H, keys, t = P[ok], N[ok], H[ok], keys[ok], t[ok]
    drawn_hash = _Near(layer.drawn.places, TEST * layer.drawn.reach)

    def stop(ids, before, after, normals):
        tt = layer.tone(after, normals)
        d = layer.spacing(tt)
        qa, sa = layer.paper.place(after)
        dd = d * sa
        ends = ~np.isfinite(dd)
        ends |= _turning(layer.paper, after, normals, layer.turning)
        ends |= drawn_hash.near(qa, TEST * 0.5 * np.where(np.isfinite(dd), dd, 0.0))
        ends |= crossing(layer.paper.place(before)[0], qa)
        return ends, tt
    rules = sm.StrokeRules(max_steps=layer.rules.max_steps, max_normal_angle=layer.rules.max_normal_angle,
                           stop_on_curvature_sign=layer.rules.stop_on_curvature_sign, region=layer.rules.region,
                           stop=stop)
    flock = np.arange(len(P))
    if layer.flock_size > 1:           # each seed a flock, side by side across its heading (Smarticles 4)
        P, H, flock, keys = spawn_flocks(P, N, H, layer.flock_size, layer.spacing(t), keys)
        t = np.repeat(t, layer.flock_size)
    lines = sm.both_ways(layer.ev, P, H, keys, layer.flow, layer.step, layer.weights, rules, flock=flock, values=t)
    return _taken(layer, lines, keys)


class _Near:
    """Points with reaches, hashed once: which of some other points come closer to one of
    them than their two reaches."""

    def __init__(self, places, reach):
        self.places, self.reach = np.asarray(places, float).reshape(-1, 3), np.asarray(reach, float)

    def near(self, Q, reach):
        out = np.zeros(len(Q), bool)
        if len(self.places) and len(Q):
            i, _ = close_pairs(Q, reach, self.places, self.reach)
            out[i] = True
        return out


def _taken(layer, lines, keys):
    """The lines of a generation taken in order, each cut where it comes (within TEST of
    the spacing) to a line taken before it, and dropped where its seed does (within the
    spacing); the visible runs of what is left as strokes, whose places join the drawn,
    and their points' tones and steps from their seeds."""
    if not lines:
        return [], []
    owner = np.concatenate([np.full(len(p), j) for j, (_, p, _, _, _) in enumerate(lines)])
    local = np.concatenate([np.arange(len(p)) for _, p, _, _, _ in lines])
    seed = np.array([s for *_, s in lines])
    Pall = np.concatenate([p for _, p, _, _, _ in lines])
    Tall = np.concatenate([t for _, _, _, t, _ in lines])
    Q, scale = layer.paper.place(Pall)
    d = layer.spacing(Tall) * scale
    d = np.where(np.isfinite(d), d, 0.0)
    i, j = close_pairs(Q, TEST * 0.5 * d, Q, TEST * 0.5 * d)
    other = owner[i] != owner[j]
    i, j = i[other], j[other]
    later = owner[i] > owner[j]                 # the pairs of a point and one of a line before its own
    i, j = i[later], j[later]
    si, sj = close_pairs(Q[_seed_rows(lines)], CLEAR * 0.5 * d[_seed_rows(lines)], Q, CLEAR * 0.5 * d)
    seed_i = owner[_seed_rows(lines)][si]
    keepS = owner[sj] < seed_i
    seed_i, sj = seed_i[keepS], sj[keepS]
    lo = np.zeros(len(lines), np.int64)
    hi = np.array([len(p) for _, p, _, _, _ in lines])
    taken = np.zeros(len(lines), bool)
    by_i = np.argsort(owner[i], kind="stable")
    i, j = i[by_i], j[by_i]
    starts = np.searchsorted(owner[i], np.arange(len(lines) + 1))
    sstarts = np.searchsorted(np.sort(seed_i), np.arange(len(lines) + 1))
    sj = sj[np.argsort(seed_i, kind="stable")]
    for k in range(len(lines)):
        b = sj[sstarts[k]:sstarts[k + 1]]
        if len(b) and _alive(owner[b], local[b], taken, lo, hi).any():
            hi[k] = 0
            continue
        a, b = i[starts[k]:starts[k + 1]], j[starts[k]:starts[k + 1]]
        hit = a[_alive(owner[b], local[b], taken, lo, hi)]
        pos = local[hit]
        ahead, behind = pos[pos > seed[k]], pos[pos < seed[k]]
        if (pos == seed[k]).any():
            hi[k] = 0
            continue
        hi[k] = ahead.min() if len(ahead) else hi[k]
        lo[k] = behind.max() + 1 if len(behind) else 0
        taken[k] = hi[k] - lo[k] >= SHORTEST
    out, tones = [], []
    kept = [(k, lines[k]) for k in range(len(lines)) if taken[k]]
    if not kept:
        return out, tones
    pieces = [(p[lo[k]:hi[k]], n[lo[k]:hi[k]], t[lo[k]:hi[k]], keys[idx]) for k, (idx, p, n, t, _) in kept]
    sizes = np.array([len(p) for p, _, _, _ in pieces])
    P = np.concatenate([p for p, _, _, _ in pieces])
    N = np.concatenate([n for _, n, _, _ in pieces])
    T = np.concatenate([t for _, _, t, _ in pieces])
    rel = np.concatenate([np.arange(lo[k], hi[k]) - seed[k] for k, _ in kept]).astype(float)   # steps from the seed
    rows = np.concatenate([np.flatnonzero(owner == k)[lo[k]:hi[k]] for k, _ in kept])
    layer.drawn.add(Q[rows], 0.5 * d[rows])
    r = 0.5 * width(T, layer.radius, layer.contrast)
    at = np.cumsum(sizes) - sizes
    for k, runs in enumerate(visible_marks(layer.sight, P, sizes, layer.paper.eye, N)):
        for run in runs:
            run = run._replace(a=at[k] + run.a, b=at[k] + run.b)
            pts = run_points(P, run)
            out.append(Stroke(pts, piece(r, run), np.ones(len(pts)), mark=int(pieces[k][3])))
            tones.append((piece(T, run), piece(rel, run)))
    return out, tones


def _seed_rows(lines):
    first = np.cumsum([0] + [len(p) for _, p, _, _, _ in lines[:-1]])
    return first + np.array([s for *_, s in lines])


def _alive(owner, local, taken, lo, hi):
    """Which points (of their lines, at their places along them) belong to a line taken."""
    return taken[owner] & (local >= lo[owner]) & (local < hi[owner])


def _beside(layer, strokes, tones):
    """The seeds beside the lines just drawn: at every SEED_EVERY-th step of each from its
    seed, SIDE spacings to either side on the paper, moved onto the surface, heading along
    the line; their keys from the line's and the step, their order the lines' and then
    along them."""
    empty = (np.zeros((0, 3)),) * 3 + (np.zeros(0, np.uint64), np.zeros(0), np.zeros(0, np.int64))
    rows = []
    for s, (v, rel) in zip(strokes, tones):
        k = np.arange(1, len(s.points) - 1)
        k = k[(rel[k] == np.round(rel[k])) & (np.round(rel[k]) % SEED_EVERY == 0)]   # (not a run's end between steps)
        if len(k):
            rows.append((s, v, rel, k))
    if not rows:
        return empty
    P = np.concatenate([s.points[k] for s, _, _, k in rows])
    T = np.concatenate([s.points[k + 1] - s.points[k - 1] for s, _, _, k in rows])
    t = np.concatenate([v[k] for _, v, _, k in rows])
    # a seed's key: its line's and its step from the line's seed (the same however the line's ends fall)
    base = np.concatenate([keyed.combine(np.full(len(k), s.mark, np.uint64), (rel[k] + STEPS_OFF).astype(np.int64))
                           for s, _, rel, k in rows])
    _, g = layer.ev.field_grad(P)
    N = -g / np.maximum(np.linalg.norm(g, axis=1, keepdims=True), 1e-300)
    T = T - np.einsum("ij,ij->i", T, N)[:, None] * N
    T /= np.maximum(np.linalg.norm(T, axis=1, keepdims=True), 1e-300)
    S = np.cross(N, T)
    q0, scale = layer.paper.place(P)
    eps = 1e-3 * layer.step
    grows = np.linalg.norm(layer.paper.place(P + eps * S)[0] - q0, axis=1) / eps       # paper per model unit
    d = layer.spacing(t) * scale
    far = SIDE * d / np.maximum(grows, 1e-300)
    X = np.concatenate([P + far[:, None] * S, P - far[:, None] * S])
    X, f, g = project(layer.ev, X, ONTO)
    keys = keyed.combine(np.concatenate([base, base]), np.repeat([1, 2], len(P)).astype(np.uint64), SIDE_SALT)
    ok = on_surface(f, layer.ev.iso, NEAR_SURFACE)
    X, g, keys = X[ok], g[ok], keys[ok]
    H = np.concatenate([T, T])[ok]
    N = -g / np.maximum(np.linalg.norm(g, axis=1, keepdims=True), 1e-300)
    rank = np.arange(len(X))
    keep = layer.paper.facing(X, N)
    if layer.rules.region is not None:
        keep &= layer.rules.region.contains(X)
    X, N, H, keys, rank = X[keep], N[keep], H[keep], keys[keep], rank[keep]
    H = H - np.einsum("ij,ij->i", H, N)[:, None] * N
    H /= np.maximum(np.linalg.norm(H, axis=1, keepdims=True), 1e-300)
    t = layer.tone(X, N)
    keep = np.isfinite(layer.spacing(t))
    X, N, H, keys, t, rank = X[keep], N[keep], H[keep], keys[keep], t[keep], rank[keep]
    seen = visible(layer.sight, X, layer.paper.eye, N)
    return X[seen], N[seen], H[seen], keys[seen], t[seen], rank[seen]


