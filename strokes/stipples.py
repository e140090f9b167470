"""Stipples (Smarticles 7): dots at the steps of smarticles wandering from the marks in
shade (model.marks), each drawn by its own shade, kept apart on the surface, and drawn
finer where they crowd together on the paper (near a silhouette), so that no two touch.
"""
import numpy as np

from . import smarticles as sm
from ..blackboard.board import pairs_within
from ..model import keyed
from .data import Stroke
from .layers import SHADE, chosen_for_shade, direction_field, headings, lighting, tone
from .visibility import visible

SPACING = 5             # which of two stipples too close together is left out (a salt, model.keyed)
STIPPLE_GAP = 1.1       # stipples keep this many times their radii's sum apart (on the surface and the paper)


def stipples(ev, marks, eye, light_dir, step, every=3, steps=30, lower=0.2, upper=0.55, radius=0.004,
             region=None, contrast=1.0, paths=None, every_path=False, drawn=(), spacing=None, sight=None,
             lines=()):
    """One-point strokes at every ``every``-th step of wandering smarticles started at
    the marks in shade: each dot is drawn as its own shade says (in the penumbra at
    random, by its own key: a light tone is no trail of one smarticle's dots), kept
    apart on the surface (``spacing``: a :class:`Spacing` that holds the dots the
    layer's parts before kept, seen or not; a new one without), and the visible ones
    drawn finer where they would touch on the paper (:func:`fitted`, also against the
    dots ``drawn`` before and the ``lines``: the visible outlines); each dot's mark is
    its smarticle's key and step (``paths``, ``every_path``: as for :func:`hatching`;
    ``sight``: what hides the dots, a strokes.visibility.Sight: default the model's own
    solid alone)."""
    every = int(every)
    if every < 1:
        raise ValueError(f"the stipple step must be at least 1, got {every}")
    rules = sm.StrokeRules(max_steps=steps, max_normal_angle=np.radians(80), stop_on_curvature_sign=False,
                           region=region)

    def run(m):
        res = sm.kept(paths, m.keys)
        if res is None:
            res = sm.run_kept(paths, ev, m.points, direction_field("dir1"), step, sm.PRESETS["stipple"], rules,
                              m.keys, headings=headings(ev, m.points, "dir1", m.ref))
        return res
    if every_path and paths is not None:
        run(marks)
    lit = lighting(marks.normals, light_dir)
    m = marks.take(lit < upper)
    res = run(m)
    if not res.paths:
        return []
    D = np.concatenate([p[::every] for p in res.paths])
    Nn = np.concatenate([n[::every] for n in res.normals])
    K = np.concatenate([keyed.combine(np.full(len(range(0, len(p), every)), k, np.uint64),
                                      np.arange(0, len(p), every)) for p, k in zip(res.paths, m.keys)])
    shade = lighting(Nn, light_dir)
    keep = chosen_for_shade(shade, lower, upper, keyed.uniform(K, SHADE))
    if region is not None:
        keep &= region.contains(D)
    D, Nn, shade, K = D[keep], Nn[keep], shade[keep], K[keep]
    r, o = tone(shade, upper, radius, contrast)
    apart = (spacing if spacing is not None else Spacing()).keep(D, r, K)
    D, Nn, K, r, o = D[apart], Nn[apart], K[apart], r[apart], o[apart]
    vis = visible(ev if sight is None else sight, D, eye, Nn)
    D, K, o = D[vis], K[vis], o[vis]
    r = fitted(D, r[vis], eye, drawn, lines)
    room = r > 0                                              # none: under a dot drawn before
    D, K, r, o = D[room], K[room], r[room], o[room]
    return [Stroke(p[None], r[i:i + 1], o[i:i + 1], dots=True, mark=int(k)) for i, (p, k) in enumerate(zip(D, K))]


class Spacing:
    """The stipples a layer keeps on the surface, over its parts: each part's dots keep
    apart from the dots the parts before it kept (hidden ones too, so what is kept does
    not depend on the view)."""

    def __init__(self):
        self.points, self.radii = np.zeros((0, 3)), np.zeros(0)

    def keep(self, P, radii, keys):
        """Which of the dots keep apart (:func:`spaced`) from each other and from the
        dots kept before; the kept ones are kept here too."""
        apart = spaced(P, radii, keys, self.points, self.radii)
        self.points = np.vstack([self.points, np.asarray(P, float).reshape(-1, 3)[apart]])
        self.radii = np.concatenate([self.radii, np.asarray(radii, float)[apart]])
        return apart


def spaced(P, radii, keys, before=np.zeros((0, 3)), before_radii=np.zeros(0)):
    """Which of the dots at ``P`` (with their ``radii`` and marks' ``keys``) keep apart on
    the surface: taken in the order of the numbers their keys draw (model.keyed),
    highest first, a dot is kept unless a kept one, or one of the dots ``before`` (with
    their ``before_radii``), is closer than STIPPLE_GAP times their radii's sum (two
    equal numbers, which practically never happen, in the order the dots come). The
    order is the dots' own and the test is in the model's space, so the same dots are
    kept from every side (a turning view keeps them)."""
    keep = np.ones(len(P), bool)
    if len(P) == 0:
        return keep
    radii = np.asarray(radii, float)
    if len(before):
        Q, rq = np.asarray(before, float), np.asarray(before_radii, float)
        i, j = pairs_within(P, Q, STIPPLE_GAP * (radii.max() + rq.max()))
        keep[i[((P[i] - Q[j]) ** 2).sum(1) < (STIPPLE_GAP * (radii[i] + rq[j])) ** 2]] = False
    i, j = pairs_within(P, P, STIPPLE_GAP * 2.0 * radii.max())
    close = (i != j) & (((P[i] - P[j]) ** 2).sum(1) < (STIPPLE_GAP * (radii[i] + radii[j])) ** 2)
    i, j = i[close], j[close]
    # each dot's place in the order (ties, if any, by position): a dot is decided once every
    # undecided neighbour comes after it (kept), or a kept neighbour took its place (left out)
    place = np.empty(len(P), np.int64)
    place[np.lexsort((np.arange(len(P)), keyed.uniform(keys, SPACING)))[::-1]] = np.arange(len(P))
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
