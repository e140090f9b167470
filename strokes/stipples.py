"""Stipples (Smarticles 7): dots at the steps of smarticles wandering from the marks,
their density and size set by the tone the light asks for (strokes.tone) as the eye
sees them: a blue-noise set on the paper (Secord 2002's weighted stippling, reached by
taking the wandering smarticles' steps in their keys' order and leaving out each one
closer than the tone's spacing to one taken before: the steps are fixed on the model,
the choice among them is the view's, Vanderhaeghe et al. 2007), drawn finer beside the
visible outlines, so that no two dots touch and no dot beads a line.
"""
import numpy as np

from . import smarticles as sm
from . import tone as TN
from ..blackboard.cells import pairs_within
from ..model import keyed
from .data import Stroke
from .layers import direction_field, headings
from .paper import Placed, close_pairs
from .visibility import tone_step, visible
from ..model.projection import project
from ..model.tolerances import NEAR_SURFACE, on_surface

SPACING = 5             # the order in which the steps are taken (a salt, model.keyed)
STIPPLE_GAP = 1.1       # stipples keep this many times their radii's sum apart on the paper
PACKING = 0.55          # dots taken from a dense pool, none closer than s, cover PACKING / s^2 of the paper
SMALLEST = 0.3         # at contrast 1 a dot in the lightest tone has this share of the darkest's radius
LIGHTEST = 0.01         # a tone under this takes its spacing, with fewer dots (a share of them by chance)
LIGHT_SALT = 9          # which dots a tone under LIGHTEST keeps (a salt, model.keyed)
LIGHT_MARGIN = 0.3     # marks lit up to this much above the highlight threshold start smarticles (they wander)


def radius_of(t, radius, contrast):
    """A dot's radius at tone ``t``: ``radius`` at the darkest, down to SMALLEST of it in
    the lightest at contrast 1."""
    return radius * (1.0 - float(contrast) * (1.0 - SMALLEST) * (1.0 - TN.darkness(t)))


def spacing_of(t, r):
    """How far apart dots of radius ``r`` stand for a tone ``t`` (the share of the paper
    they cover), never under STIPPLE_GAP times their diameter."""
    with np.errstate(divide="ignore"):
        s = r * np.sqrt(PACKING * np.pi / np.maximum(np.asarray(t, float), 1e-300))
    return np.maximum(s, 2.0 * STIPPLE_GAP * r)


def stipples(ev, marks, paper, shadows, step, lower, upper, contrast=1.0, radius=0.004, steps=30, every=1,
             region=None, paths=None, every_path=False, dots=None, sight=None, lines=(), share="all"):
    """Dots at every ``every``-th step of wandering smarticles started at the marks near
    or in shade, and about each step (:func:`around`): of those that face the eye and
    want ink (strokes.tone: their ``share`` of it, strokes.tone.coverage), taken in
    their keys' order, each one left out that comes closer on the paper
    (strokes.paper.Paper) to one taken before, or to the ``dots`` drawn by the layer's
    parts before, than the spacing their tones ask for
    (:func:`spacing_of`), and each hidden one (then the choice is made again without
    it); each dot sized by its tone (:func:`radius_of`) and finer where it comes near a
    line of ``lines`` (the visible outlines, :func:`fitted`). Each dot's mark is its
    smarticle's key, step and place about it (``paths``, ``every_path``: as for
    strokes.layers.hatching; ``shadows``: the light, strokes.tone.Shadows; ``sight``: what
    hides the dots, a strokes.visibility.Sight: default the model's own solid alone)."""
    every = int(every)
    if every < 1:
        raise ValueError(f"the stipple step must be at least 1, got {every}")
    sight = ev if sight is None else sight
    dots = Placed() if dots is None else dots
    rules = sm.StrokeRules(max_steps=steps, max_normal_angle=np.radians(80), stop_on_curvature_sign=False,
                           region=region)

    def run(m):
        res = sm.kept(paths, m.keys)
        if res is None:
            res = sm.run_kept(paths, ev, m.points, direction_field("straight"), step, sm.PRESETS["stipple"], rules,
                              m.keys, headings=headings(ev, m.points, "dir1", m.ref), bends=False)
        return res
    if every_path and paths is not None:
        run(marks)
    m = marks.take(shadows.light(marks.points, marks.normals) < upper + LIGHT_MARGIN)
    res = run(m)
    if not res.paths:
        return []
    counts = [len(range(0, len(p), every)) for p in res.paths]
    D = np.concatenate([p[::every] for p in res.paths])
    Nn = np.concatenate([n[::every] for n in res.normals])
    K = np.concatenate([keyed.combine(np.full(c, k, np.uint64), np.arange(0, c * every, every))
                        for c, k in zip(counts, m.keys)])
    ref = np.repeat(m.ref, counts, axis=0)
    lit = shadows.light(D, Nn)
    near = lit < upper + LIGHT_MARGIN
    D, Nn, K, ref, lit = D[near], Nn[near], K[near], ref[near], lit[near]
    shadowed = (lit == 0) & (TN.lambert(Nn, shadows.L) > 0)
    others = np.searchsorted(AROUND_TONES, TN.tone(lit, lower, upper, contrast) / TN.DARKEST, "right")
    D, Nn, K, shadowed = around(ev, D, Nn, ref, K, shadowed, AROUND * step, others)
    keep = paper.facing(D, Nn)
    if region is not None:
        keep &= region.contains(D)
    D, Nn, K, shadowed = D[keep], Nn[keep], K[keep], shadowed[keep]
    t = TN.coverage(TN.tone(np.where(shadowed, 0.0, TN.lambert(Nn, shadows.L)), lower, upper, contrast), share)
    # the lightest tones: the lightest's spacing, fewer dots (each by its key's chance)
    inked = (t > 0) & (keyed.uniform(K, LIGHT_SALT) * LIGHTEST < t)
    D, Nn, K, t = D[inked], Nn[inked], K[inked], np.maximum(t[inked], LIGHTEST)
    r = radius_of(t, radius, contrast)
    Q, scale = paper.place(D)
    half = 0.5 * spacing_of(t, r) * scale
    apart = _seen_apart(sight, paper, D, Nn, Q, half, K, dots)
    D, K, r, Q, half = D[apart], K[apart], r[apart], Q[apart], half[apart]
    dots.add(Q, half)             # (a dot on a line keeps its room: later parts do not hang on the lines)
    r = fitted(D, r, paper.eye, (), lines)
    room = r > 0                                              # none: on a line
    D, K, r = D[room], K[room], r[room]
    return [Stroke(p[None], r[i:i + 1], np.ones(1), dots=True, mark=int(k)) for i, (p, k) in enumerate(zip(D, K))]


AROUND = 1.0            # steps: the radius about a wandering step where its other dots may fall
AROUND_TONES = (0.05, 0.2, 0.45)     # tones (shares of the darkest) from which a step has 1, 2, 3 others about it


def around(ev, P, N, ref, keys, shadowed, radius, others):
    """The steps and ``others`` points (a count each) about each, within ``radius`` in its
    tangent plane (a frame of its normal and its mark's reference direction, so fixed on
    the model), each at a place its key draws (model.keyed), moved onto the surface: the
    dots' candidates, where a darker tone wants them denser, with their keys and whether
    their step is in a cast shadow (its others are too). A point that does not reach the
    surface is left out."""
    others = np.asarray(others, np.int64)
    owner = np.repeat(np.arange(len(P)), others)
    if len(owner) == 0:
        return P, N, keys, shadowed
    e1 = ref - np.einsum("ij,ij->i", ref, N)[:, None] * N
    e1 /= np.maximum(np.linalg.norm(e1, axis=1, keepdims=True), 1e-300)
    e2 = np.cross(N, e1)
    which = np.arange(len(owner)) - np.repeat(np.cumsum(others) - others, others) + 1
    K = keyed.combine(keys[owner], which)
    u = keyed.uniform(K, AROUND_SALT, count=2).reshape(-1, 2)
    rho, phi = radius * np.sqrt(u[:, 0]), 2 * np.pi * u[:, 1]
    X = P[owner] + (rho * np.cos(phi))[:, None] * e1[owner] + (rho * np.sin(phi))[:, None] * e2[owner]
    X, f, g = project(ev, X, ONTO)
    ok = on_surface(f, ev.iso, NEAR_SURFACE)
    G = -g[ok] / np.maximum(np.linalg.norm(g[ok], axis=1, keepdims=True), 1e-300)
    return (np.vstack([P, X[ok]]), np.vstack([N, G]), np.concatenate([keys, K[ok]]),
            np.concatenate([shadowed, shadowed[owner][ok]]))


AROUND_SALT = 8         # where the other dots about a step fall (a salt, model.keyed)
ONTO = 3                # Newton steps that put them onto the surface


def _seen_apart(sight, paper, D, N, Q, half, K, dots):
    """Which candidates keep apart (:func:`spaced`) among the visible ones: the choice is
    made, the chosen tested for visibility, and where one is hidden every candidate that
    could take its room too (hidden parts of the paper are whole regions), and the
    choice made again without the hidden ones until every chosen one is seen (a hidden
    candidate takes no room on the paper)."""
    hidden = ~_first_in_cells(Q, half, K)
    tested = hidden.copy()
    step = tone_step(sight)
    while True:
        ok = np.flatnonzero(~hidden)
        chosen = np.zeros(len(D), bool)
        chosen[ok[spaced(Q[ok], half[ok], K[ok], dots.places, dots.reach)]] = True
        new = np.flatnonzero(chosen & ~tested)
        if len(new) == 0:
            return chosen
        tested[new] = True
        seen = visible(sight, D[new], paper.eye, N[new], step=step)
        if seen.all():
            return chosen
        lost = new[~seen]
        hidden[lost] = True
        _, near = close_pairs(Q[lost], 2.0 * half[lost], Q, half)
        near = np.unique(near[~tested[near]])
        tested[near] = True
        hidden[near[~visible(sight, D[near], paper.eye, N[near], step=step)]] = True


def _first_in_cells(Q, reach, keys):
    """Which candidates come first, in :func:`spaced`'s order, in their cell of the paper
    (cells as wide as their reach, rounded down to a power of 2): the others would be
    left out for it wherever it is kept, and a pool far denser than its dots only costs."""
    if len(Q) == 0:
        return np.zeros(0, bool)
    level = np.floor(np.log2(np.maximum(reach, 1e-300))).astype(np.int64)
    cell = np.floor(Q / np.exp2(level)[:, None]).astype(np.int64)
    rows = np.column_stack([level, cell])
    order = np.lexsort((-keyed.uniform(keys, SPACING),) + tuple(rows.T[::-1]))
    r = rows[order]
    first = np.r_[True, (r[1:] != r[:-1]).any(axis=1)]
    out = np.zeros(len(Q), bool)
    out[order[first]] = True
    return out


def spaced(P, reach, keys, before=np.zeros((0, 3)), before_reach=np.zeros(0), first=None):
    """Which of the points ``P`` (with their ``reach``es and marks' ``keys``) keep apart:
    taken in the order of the numbers their keys draw (model.keyed), highest first (or
    of ``first``, lowest first), a point is kept unless a kept one, or one of the points
    ``before`` (with their ``before_reach``), is closer than their two reaches (two
    equal numbers, which practically never happen, in the order the points come). The
    result is that of taking them one by one, computed in rounds over all of them at
    once."""
    keep = np.ones(len(P), bool)
    if len(P) == 0:
        return keep
    reach = np.asarray(reach, float)
    if len(before):
        i, _ = close_pairs(P, reach, before, before_reach)
        keep[i] = False
    i, j = close_pairs(P, reach, P, reach)
    close = (i != j) & keep[i] & keep[j]
    i, j = i[close], j[close]
    # each point's place in the order (ties, if any, by position): a point is decided once
    # every undecided neighbour comes after it (kept), or a kept neighbour took its place (left out)
    place = np.empty(len(P), np.int64)
    if first is None:
        place[np.lexsort((np.arange(len(P)), keyed.uniform(keys, SPACING)))[::-1]] = np.arange(len(P))
    else:
        place[np.lexsort((np.arange(len(P)), np.asarray(first)))] = np.arange(len(P))
    open_ = keep.copy()
    while open_.any():
        live = open_[i] & open_[j]
        first = np.full(len(P), len(P))
        np.minimum.at(first, i[live], place[j[live]])
        won = open_ & (place < first)
        lost = np.zeros(len(P), bool)
        lost[j[won[i]]] = True
        lost &= open_ & ~won
        keep[lost] = False
        open_ &= ~(won | lost)
    return keep


def on_paper(P, radii, eye):
    """Dots as the eye sees them: their directions from it (unit vectors) and their
    radii over their distances (the angles they span), so that two dots' distance is
    their distance on the paper, foreshortening and perspective included."""
    V = np.asarray(P, float).reshape(-1, 3) - np.asarray(eye, float)
    d = np.linalg.norm(V, axis=1)
    return V / d[:, None], np.asarray(radii, float) / d


def fitted(P, radii, eye, drawn=(), lines=()):
    """The dots' radii, each made smaller where on the paper (:func:`on_paper`) it would
    come closer to another dot, or to one of ``drawn``, or to a line of ``lines``
    (strokes, each a polyline with its radii), than STIPPLE_GAP times their radii's sum:
    where the surface turns away (near a silhouette) dots apart on the surface crowd
    together on the paper, and there they are drawn finer instead of running into
    dashes, and a dot on a line does not bead it. A radius changes smoothly as the view
    turns: no dot comes or goes for it."""
    radii = np.asarray(radii, float)
    if len(P) == 0:
        return radii
    U, a = on_paper(P, radii, eye)
    room = a.copy()                      # the angle each dot may span
    i, j = pairs_within(U, U, STIPPLE_GAP * 2.0 * a.max())
    other = i != j
    np.minimum.at(room, i[other], np.linalg.norm(U[i[other]] - U[j[other]], axis=1) / (2.0 * STIPPLE_GAP))
    if len(drawn):
        W, b = on_paper([s.points[0] for s in drawn], [s.radius[0] for s in drawn], eye)
        i, j = pairs_within(U, W, STIPPLE_GAP * (a.max() + b.max()))
        np.minimum.at(room, i, np.maximum(np.linalg.norm(U[i] - W[j], axis=1) / STIPPLE_GAP - b[j], 0.0))
    lines = [(np.vstack([s.points, s.points[:1]]), np.concatenate([s.radius, s.radius[:1]])) if s.cyclic
             else (s.points, s.radius) for s in lines if len(s.points) > 1]          # a loop's closing segment too
    if lines:
        A, ra = on_paper(np.concatenate([p[:-1] for p, _ in lines]),
                         np.concatenate([np.maximum(r[:-1], r[1:]) for _, r in lines]), eye)
        B, _ = on_paper(np.concatenate([p[1:] for p, _ in lines]), np.zeros(len(A)), eye)
        half = 0.5 * np.linalg.norm(B - A, axis=1)
        i, j = pairs_within(U, 0.5 * (A + B), STIPPLE_GAP * (a.max() + ra.max()) + half.max())
        AB = B[j] - A[j]
        t = np.clip(np.einsum("ij,ij->i", U[i] - A[j], AB) / np.maximum(np.einsum("ij,ij->i", AB, AB), 1e-300), 0, 1)
        foot = A[j] + t[:, None] * AB                  # on the chord: back onto the sphere of directions
        gap = np.linalg.norm(U[i] - foot / np.linalg.norm(foot, axis=1, keepdims=True), axis=1)
        np.minimum.at(room, i, np.maximum(gap / STIPPLE_GAP - ra[j], 0.0))
    return radii * (room / a)
