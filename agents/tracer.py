"""Tracing feature outlines with a predictor-corrector step (paper section 6), batched
over every tracing task: one step per task per system iteration.

Predictor: move along the current tangent by the step h. Corrector: project onto the
surface, bracket the outline across the tangent (in the tangent plane, on both sides;
a crease bracket dips into the solid), and bisect the bracket to the outline (every
bisection point is projected onto the surface). A crease task is a team of two agents,
one on each side of the crease (the bracket ends): dual tracking. A seed starts a task
each way along its outline where agents are free for both (else one task goes forwards,
then backwards from its seed). A task ends when its outline closes on its start, meets
an outline of the same kind already traced, or is lost (no bracket).
"""
from typing import NamedTuple

import numpy as np

from ..model.branches import apart
from ..model.tolerances import on_surface
from ..model.vectors import cross
from . import sheets
from .asks import run
from .bisection import bisect, bisect_some
from .surface import CREASE, CURV, SIL, SUG, WEDGE, crease_estimate, unit

SIDE = 0.05         # a crease team's agents keep this share of the step to either side of it
ON_SILHOUETTE = 1e-7  # |n.v| of a silhouette point (a Newton-located one: about 1e-12)
SMOOTH = 0.5        # a silhouette Newton step whose normal at P, predicted back from X through
                    # the Hessian, is off by this much of the crease angle crossed a crease
FAR = 2.5           # a step longer than this many steps jumped off its outline


class Step(NamedTuple):
    """One trace step of every task: the new points, normals, tangents and refs, the
    team's side positions and their normals (the two sheets', for a crease), the
    field and gradient at the new points, and whether each task is still on its outline."""
    X: np.ndarray
    n: np.ndarray
    T: np.ndarray
    ref: np.ndarray
    A: np.ndarray
    B: np.ndarray
    nA: np.ndarray
    nB: np.ndarray
    f: np.ndarray
    g: np.ndarray
    ok: np.ndarray
    pins: np.ndarray            # (m, 2, sites) the sides' branch records (creases; model.branches)


def silhouette_kept(surface, X, G, bend, n_back, crease_angle):
    """Whether Newton-located silhouette points X (gradients G, the Hessian times the way
    back to points of known normals ``n_back``: Surface.silhouette_newton_steps) count:
    the normal predicted back there through the Hessian must be the known one (a point
    across a crease, a jump of the gradient, is refused), and the point must be on the
    silhouette (Newton's last step can be below tol where the Hessian is huge, beside a
    crease, while n.v is not yet zero)."""
    ok = np.einsum("ij,ij->i", surface.normals(G - bend), n_back) > np.cos(SMOOTH * crease_angle)
    return ok & (np.abs(np.einsum("ij,ij->i", surface.normals(G), surface.view.towards_eye(X))) <= ON_SILHOUETTE)


def levels_hold(surface, kinds, ok, X, g, T):
    """Whether points X (gradients g, line tangents T) of curvature-sign lines and
    suggestive contours, among those ``ok``, are points of such lines
    (Surface.curvature_crossings, Surface.suggestive_valid); the other kinds' pass."""
    hold = np.ones(len(X), bool)
    cv = np.flatnonzero(ok & (kinds == CURV))
    if len(cv):
        hold[cv] = surface.curvature_crossings(X[cv], g[cv], T[cv])
    sg = np.flatnonzero(ok & (kinds == SUG))
    if len(sg):
        hold[sg] = surface.suggestive_valid(X[sg], g[sg])
    return hold


def level_tangent(surface, kinds, X, n, ref, eps):
    """The direction along which a signed quantity stays zero: n x (its surface gradient),
    the gradient estimated from central differences on the surface."""
    e1 = unit(cross(n, np.where(np.abs(n[:, :1]) < 0.9, [[1.0, 0, 0]], [[0, 1.0, 0]])))
    e2 = cross(n, e1)
    pts = np.concatenate([X + eps * e1, X - eps * e1, X + eps * e2, X - eps * e2])
    P, _, g = surface.project(pts)
    s = surface.signs(np.concatenate([kinds] * 4), P, g, np.concatenate([ref] * 4)).reshape(4, -1)
    G = (s[0] - s[1])[:, None] * e1 + (s[2] - s[3])[:, None] * e2
    return unit(cross(n, G))


class Seeds(NamedTuple):
    """Refined seeds (:func:`refine_seeds`)."""
    X: np.ndarray               # the outline point
    n: np.ndarray               # its normal
    T: np.ndarray               # a first tangent
    ref: np.ndarray             # the crease ref (n_A - n_B)
    A: np.ndarray               # the bracket ends (narrowed)
    B: np.ndarray
    valid: np.ndarray           # a real outline point (not a false alarm, nor a smooth bend taken for a crease)
    pins: np.ndarray            # (m, 2, sites) the ends' branch records (model.branches)
    open: np.ndarray            # bisection paused: A, B is the narrowed bracket to go on from


def refine_seeds(surface, kinds, a, b, tol, crease_angle, pause=None):
    """Seeds from brackets (e.g. polygon edges), as :class:`Seeds`. The ends' branch
    records are taken for crease brackets and for silhouette brackets Newton did not
    settle (NOT_REACHED elsewhere).

    A crease bracket whose ends' records chose alike at every site is a smooth bend (no
    max or min switches between them): invalid at once. The others go to the crease
    point by Newton's method on the two sheets (agents.sheets), and to bisection where
    that does not converge. With ``pause`` (a number of iterations), a bracket the
    bisection has not settled within that many is left open, not valid, with its
    narrowed ends: the caller refines it again later, Newton first (from a narrower
    bracket it settles more often)."""
    a0, b0 = np.asarray(a, float), np.asarray(b, float)
    m = len(a0)
    P, _, g = surface.project(np.concatenate([a0, b0]), anchor=np.concatenate([b0, a0]))   # one batch
    a, b, ga, gb = P[:m], P[m:], g[:m], g[m:]
    na, nb = surface.normals(ga), surface.normals(gb)
    ref = na - nb
    eps = 0.25 * float(np.linalg.norm(b - a, axis=1).mean()) if len(a) else 1.0
    s = surface.signs(np.concatenate([kinds, kinds]), P, g, np.concatenate([ref, ref]))
    sA, sB = s[:m], s[m:]
    # silhouettes by Newton's method (quadratic; regula falsi on n.v crawls where it
    # bends), in the plane through the bracket's interpolated crossing across the
    # outline; the others, and those Newton does not settle, by bisection
    X, gX = np.zeros((m, 3)), np.zeros((m, 3))
    A, B, nA, nB = np.zeros((m, 3)), np.zeros((m, 3)), np.zeros((m, 3)), np.zeros((m, 3))
    valid = np.zeros(m, bool)
    tangent = np.zeros((m, 3))
    by_newton = np.zeros(m, bool)
    use = sheets.usable(surface)
    pins = np.full((m, 2, surface.ev.sites.count if use else 0), -2, np.int32)
    sep = np.zeros(m, bool)
    flips = (sA > 0) != (sB > 0)
    sil = np.flatnonzero((kinds == SIL) & flips)
    cr = np.flatnonzero((kinds == CREASE) & flips & use)

    def silhouettes():
        # a converged point is on the surface with n.v = 0 where the field is smooth: a
        # silhouette point, within the bracket's length of it (across a crease, where n.v
        # jumps through zero, Newton finds none and the bisection rejects the bracket)
        d = b[sil] - a[sil]
        u = np.clip(sA[sil] / (sA[sil] - sB[sil]), 0.0, 1.0)[:, None]
        T = unit(cross(unit((1.0 - u) * na[sil] + u * nb[sil]), d))
        Xs, _, Gs, Ts, conv, _ = yield from surface.silhouette_newton_steps(a[sil] + u * d, T,
                                                                            np.linalg.norm(d, axis=1), tol)
        got = sil[conv]
        X[got] = A[got] = B[got] = Xs[conv]
        gX[got] = Gs[conv]
        nA[got] = nB[got] = surface.normals(Gs[conv])
        tangent[got] = Ts[conv]
        valid[got] = by_newton[got] = True
        rest = sil[~conv] if use else sil[:0]
        if len(rest):
            pins[rest], sep[rest] = yield from sheets.record_ends_steps(surface, a[rest], b[rest])
            silx = rest[sep[rest]]
            if len(silx):
                # a silhouette bracket across a crease where neither sheet's n.v changes
                # sign between the ends: the sign change is the crease's, no silhouette
                # (not valid)
                no = yield from sheets.no_silhouette_steps(surface, a[silx], b[silx], sA[silx], sB[silx], pins[silx])
                by_newton[silx[no]] = True

    def creases():
        pins[cr], sep[cr] = yield from sheets.record_ends_steps(surface, a[cr], b[cr])
        by_newton[cr[~sep[cr]]] = True      # smooth between the ends: not valid
        c = cr[sep[cr]]
        if len(c) == 0:
            return
        w = np.linalg.norm(b[c] - a[c], axis=1)
        mid = 0.5 * (a[c] + b[c])
        Tc = unit(cross(na[c], nb[c]))
        X0 = crease_estimate(a[c], b[c], na[c], nb[c], mid)
        Xc, gAc, gBc, _, gc, conv = yield from sheets.crease_newton_steps(surface, X0, mid, Tc, pins[c], WEDGE * w, tol)
        met = np.flatnonzero(conv)
        if len(met):            # the pinned sheets may meet past a junction: not the bracket's crease
            conv[met] = (yield from sheets.switches_steps(surface, Xc[met], surface.normals(gAc[met]),
                                                          surface.normals(gBc[met]), b[c[met]] - a[c[met]],
                                                          SIDE * w[met]))[0]
        got = c[conv]
        X[got], gX[got], A[got], B[got] = Xc[conv], gc[conv], a[got], b[got]
        nA[got], nB[got] = surface.normals(gAc[conv]), surface.normals(gBc[conv])
        valid[got] = by_newton[got] = True

    # the silhouettes' chain (Newton, then the branch records and the sheets' n.v where
    # it did not settle) beside the creases' (the records, then the sheets' Newton), on
    # shared evaluations (agents.asks); they write disjoint rows
    run(surface.ev, silhouettes() if len(sil) else None, creases() if len(cr) else None)
    # a crease bracket stops at sqrt(tol * its length): sheets curved no tighter than the
    # bracket is long then put the crossing from the tangent planes within tol
    finish = np.sqrt(tol * np.linalg.norm(b0 - a0, axis=1))
    opened = np.zeros(m, bool)
    rest = np.flatnonzero(~by_newton)
    if len(rest):
        iters = 60 if pause is None else pause
        out, more = bisect_some(surface, kinds[rest], None, None, ref[rest], tol, iters, crease_angle,
                                ends=(a[rest], ga[rest], sA[rest], b[rest], gb[rest], sB[rest]),
                                finish=finish[rest], pause=pause is not None)
        for arr, val in zip((X, gX, A, B, nA, nB, valid), out):
            arr[rest] = val
        opened[rest] = more
    cre = np.flatnonzero((kinds == CREASE) & valid & ~by_newton)
    if len(cre):
        # creases: bisect once more from the narrowed bracket with its own side normals
        x2, g2, A2, B2, nA2, nB2, v2 = bisect(surface, kinds[cre], A[cre], B[cre], nA[cre] - nB[cre], tol,
                                              crease_angle=crease_angle, finish=finish[cre])
        X[cre[v2]], gX[cre[v2]], A[cre[v2]], B[cre[v2]] = x2[v2], g2[v2], A2[v2], B2[v2]
        nA[cre[v2]], nB[cre[v2]] = nA2[v2], nB2[v2]
        if use:
            pins[cre] = sheets.record_ends(surface, A[cre], B[cre])[0]     # the sides' records, nearer the crease
    cre = kinds == CREASE
    ang = np.arccos(np.clip(np.einsum("ij,ij->i", nA, nB), -1, 1))
    # a crease must be a jump of the normal; a silhouette or curvature-sign crossing must
    # not be one (n.v and curvature jump across a crease too, and creases draw those)
    valid &= np.where(cre, ang > 0.5 * crease_angle, ang < 0.5 * crease_angle)
    n = surface.normals(gX)
    lev = np.flatnonzero(~cre & ~by_newton & valid)
    if len(lev):
        tangent[lev] = level_tangent(surface, kinds[lev], X[lev], n[lev], (nA - nB)[lev], eps)
    tangent = np.where(cre[:, None], unit(cross(nA, nB)), tangent)
    bad = ~np.all(np.isfinite(tangent), axis=1) | (np.linalg.norm(tangent, axis=1) < 0.5)
    valid &= ~bad
    fX, _ = surface.field_grad(X)
    valid &= on_surface(fX, surface.iso)
    valid &= levels_hold(surface, kinds, valid, X, gX, tangent)
    return Seeds(X, n, tangent, nA - nB, A, B, valid & ~opened, pins, opened)


def trace_step(surface, kinds, P, T, ref, h, tol, crease_angle, nP=None, pins=None, team=None, retry=None):
    """One predictor-corrector step for each task (a :class:`Step`; ok False: lost).

    Silhouettes (given ``nP``, the normals at P) are corrected by Newton's method
    (:meth:`Surface.silhouette_newton`, a few evaluations), and so are creases whose
    team has its sides' branch records (``pins``, (m, 2, sites)) and positions
    (``team``: (A, B), which way is which side) (agents.sheets); the others by
    bracketing across the tangent and bisecting (tens of evaluations), a crease's new
    records taken at its bracket's ends. A silhouette step Newton does not settle, or
    that crossed a crease, is not ok (the caller retries it with a shorter step, and
    past its shortest the silhouette ends there: at a crease, where Newton's test sees
    the normal jump; bracketing it then, tens of tiny sequential batches, found a
    point for one step in eight on the train's tails and the next step failed again).
    A crease step the sheets' Newton does not settle is bracketed, except where
    ``retry`` (per task: the caller will retry a failed step with a shorter one): it is
    not ok then, and bracketed once its step is the shortest (a shorter step mostly
    settles by Newton; bracketing costs tens of sequential batches, 15 % of the
    train's first iterations)."""
    m = len(P)
    use = sheets.usable(surface)
    if pins is None or not use:
        pins = np.full((m, 2, surface.ev.sites.count if use else 0), -2, np.int32)
    else:
        pins = pins.copy()
    X = np.zeros((m, 3))
    A_out, B_out = np.zeros((m, 3)), np.zeros((m, 3))
    nA_out, nB_out = np.zeros((m, 3)), np.zeros((m, 3))
    found = np.zeros(m, bool)
    newton = np.zeros(m, bool)                  # corrected by Newton (else bracketed)
    tangent = np.zeros((m, 3))                  # the next direction, where Newton gave one
    fX, gX = np.zeros(m), np.zeros((m, 3))      # the field and gradient at X, where Newton gave them
    sil = np.flatnonzero(kinds == SIL) if nP is not None else np.zeros(0, np.int64)
    cre = np.flatnonzero(kinds == CREASE)
    if len(cre) and team is not None:
        cre = cre[apart(pins[cre, 0], pins[cre, 1])]
    else:
        cre = cre[:0]
    # the two correctors side by side, on shared evaluations (agents.asks)
    Qc = P[cre] + h[cre, None] * T[cre]

    def creases():
        Xc, gA, gB, Fc, Gc, conv = yield from sheets.crease_newton_steps(surface, Qc, Qc, T[cre], pins[cre],
                                                                         2.0 * h[cre], tol)
        got = np.flatnonzero(conv)
        sides = np.zeros((2, len(Xc), 3))     # the team's new side points
        if len(got):            # the sheets meet on past a junction: no crease there (the trace ends)
            W = team[1][cre[got]] - team[0][cre[got]]
            conv[got], sides[0, got], sides[1, got] = yield from sheets.switches_steps(
                surface, Xc[got], surface.normals(gA[got]), surface.normals(gB[got]), W, SIDE * h[cre[got]])
        return Xc, gA, gB, Fc, Gc, conv, sides

    by_sil, by_cre = run(
        surface.ev,
        surface.silhouette_newton_steps(P[sil] + h[sil, None] * T[sil], T[sil], 2.0 * h[sil], tol, back=P[sil])
        if len(sil) else None,
        creases() if len(cre) else None)
    if len(sil):
        Xs, Fs, Gs, Ts, conv, bend = by_sil
        conv &= silhouette_kept(surface, Xs, Gs, bend, nP[sil], crease_angle)
        got = sil[conv]
        X[got] = A_out[got] = B_out[got] = Xs[conv]
        fX[got], gX[got] = Fs[conv], Gs[conv]
        nA_out[got] = nB_out[got] = surface.normals(Gs[conv])
        tangent[got] = Ts[conv]
        found[got] = newton[got] = True
    if len(cre):
        Xc, gA, gB, Fc, Gc, conv, sides = by_cre
        got = cre[conv]
        nA, nB = surface.normals(gA[conv]), surface.normals(gB[conv])
        X[got], nA_out[got], nB_out[got] = Xc[conv], nA, nB
        fX[got], gX[got] = Fc[conv], Gc[conv]
        A_out[got], B_out[got] = sides[0, conv], sides[1, conv]
        tc = unit(cross(nA, nB))
        tangent[got] = np.where(np.einsum("ij,ij->i", tc, T[got])[:, None] < 0, -tc, tc)
        found[got] = newton[got] = True
    todo = ~found
    todo[sil] = False
    if retry is not None:
        todo[cre] &= ~retry[cre]
    rest = np.flatnonzero(todo)
    if len(rest):
        Xb, Ab, Bb, nAb, nBb, fb = _bracket_step(surface, kinds[rest], P[rest], T[rest], ref[rest], h[rest],
                                                 tol, crease_angle)
        X[rest], A_out[rest], B_out[rest], nA_out[rest], nB_out[rest] = Xb, Ab, Bb, nAb, nBb
        found[rest] = fb
        cb = rest[fb & (kinds[rest] == CREASE)]
        if len(cb) and use:
            pins[cb] = sheets.record_ends(surface, A_out[cb], B_out[cb])[0]
    lost = ~found
    X[lost] = P[lost]          # not moved: evaluated at a known surface point
    ok = found.copy()
    rest = np.flatnonzero(~newton)
    if len(rest):
        fX[rest], gX[rest] = surface.field_grad(X[rest])
    ok &= on_surface(fX, surface.iso)     # on the surface, or lost
    ang = np.arccos(np.clip(np.einsum("ij,ij->i", nA_out, nB_out), -1, 1))
    jumped = ang > 0.5 * crease_angle
    ok &= np.where(kinds == CREASE, jumped, ~jumped)   # a silhouette ends where it meets a crease
    step = X - P
    # a step that went backwards or jumped far is a lost trace, not progress
    adv = np.einsum("ij,ij->i", step, T)
    ok &= (adv > 0.2 * h) & (np.linalg.norm(step, axis=1) < FAR * h)
    Tn = np.where(newton[:, None], tangent, unit(step))
    # a curvature-sign line ends where the surface stops turning across it, a suggestive
    # contour where it stops being one or turns away
    ok &= levels_hold(surface, kinds, ok, X, gX, Tn)
    cre = kinds == CREASE
    ref_new = np.where(cre[:, None], nA_out - nB_out, ref)
    return Step(X, surface.normals(gX), Tn, ref_new, A_out, B_out, nA_out, nB_out, fX, gX, ok, pins)


def _bracket_step(surface, kinds, P, T, ref, h, tol, crease_angle):
    """The corrector by bracketing: project the predicted point, bracket the outline
    across the tangent at three widths, bisect every bracket that holds a crossing
    and keep each task's narrowest valid one. Returns the points, the final bracket
    ends and their normals, and whether each was found."""
    Q, _, gQ = surface.project(P + h[:, None] * T, anchor=P)
    n = surface.normals(gQ)
    W = unit(cross(n, T))
    found = np.zeros(len(P), bool)
    X = Q.copy()
    A_out, B_out = Q.copy(), Q.copy()
    nA_out, nB_out = n.copy(), n.copy()
    # brackets across the tangent at three widths, their ends projected in one batch
    widths = (0.5, 1.0, 2.0)
    m = len(P)
    d = np.concatenate([(w * h)[:, None] * W for w in widths])
    Qw, kw, rw = np.tile(Q, (3, 1)), np.tile(kinds, 3), np.tile(ref, (3, 1))
    # a crease bracket dips into the solid by half its half-width: across a sharp
    # convex edge, an end in the tangent plane over the drop-off would project back
    # onto the edge itself and never reach the far side
    sink = np.where(kw == CREASE, 0.5, 0.0)[:, None] * np.linalg.norm(d, axis=1, keepdims=True) * np.tile(n, (3, 1))
    E = surface.ends(kw, Qw + d - sink, Qw - d - sink, rw, anchor=Qw)
    crossing = ((E[2] > 0) != (E[5] > 0)).reshape(len(widths), m)
    # every bracket with a sign change is bisected in one batch (the bisection runs as
    # long as its slowest bracket, so one batch costs about the sequential calls of
    # one); each task keeps its narrowest valid one
    j, todo = np.nonzero(crossing)
    if len(todo):
        src = j * m + todo
        x, _, A, B, nA, nB, valid = bisect(surface, kw[src], None, None, rw[src], tol, crease_angle=crease_angle,
                                           ends=tuple(e[src] for e in E), finish=np.sqrt(tol * h[todo]))
        for w in range(len(widths) - 1, -1, -1):        # the narrowest valid bracket last, so it wins
            v = np.flatnonzero(valid & (j == w))
            got = todo[v]
            X[got] = x[v]
            A_out[got], B_out[got], nA_out[got], nB_out[got] = A[v], B[v], nA[v], nB[v]
            found[got] = True
    return X, A_out, B_out, nA_out, nB_out, found
