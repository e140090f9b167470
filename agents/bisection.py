"""Zero crossings of a feature outline's signed quantity between bracket ends on the
surface (agents.surface): regula falsi with the Illinois rule for silhouettes and
curvature-sign lines, the ends' tangent planes for creases, every trial point
projected onto the surface; batched over all brackets, pausable (MASSRIS agents act
once per system iteration)."""
import numpy as np

from ..model.tolerances import CONVERGED, TRIAL, on_surface
from .surface import CREASE, CURVED, WEDGE, crease_estimate, unit

CREASE_NUDGE = 0.05          # crease trial points step this fraction of the bracket off the estimate
WIDE_NUDGE = 0.25            # ... and this much after an estimate that left the bracket above 0.7
ZERO_SIGN = 1e-11            # a smooth crossing's signed quantity (n.v, or the mean curvature times the
                             # model's size) vanishes below this
PROGRESS_EVERY = 6           # bisection iterations within which a bracket must shrink to a quarter


def bisect(surface, kinds, A, B, ref, tol, iters=60, crease_angle=None, anchor=None, ends=None, finish=None):
    """:func:`bisect_some` run to the end (at most ``iters`` iterations): every
    bracket comes out found or not valid."""
    return bisect_some(surface, kinds, A, B, ref, tol, iters, crease_angle, anchor, ends, finish)[0]


def bisect_some(surface, kinds, A, B, ref, tol, iters=60, crease_angle=None, anchor=None, ends=None, finish=None,
                pause=False):
    """Zero crossings between bracket ends A, B (on the surface, opposite signs).

    Regula falsi with the Illinois modification on the segment A-B, every trial
    point projected onto the surface. Creases (where the sign jumps rather than
    crosses zero) take two trial points a little either side of where the ends'
    tangent planes meet (on curved sheets off the crease by the square of the
    bracket's width, so a bracket shrinks about twentyfold per iteration once both
    land near it; a wide bracket across a sharp wedge shrank by only about 0.86 per
    plain bisection: 40 iterations against 9), and a quarter of the bracket either
    side of it after an estimate that did not shrink the bracket below 0.7 (the
    estimate was off by more than the small nudge; the midpoint it replaced could
    widen a bracket across a sharp wedge). Trial points take two Newton steps towards
    the surface; a crease trial point whose projection does not settle near it (within
    model.tolerances.TRIAL) moves no end. Returns the crossing (the
    final bracket end on the first end's side, on the surface to rounding), its
    gradient, the final bracket ends and their normals, and whether each bracket
    held a sign change. With ``crease_angle``, a crease bracket whose end normals
    come within half of it is a smooth bend, not a crease: it stops at once, invalid
    (narrowing a smooth surface only brings the normals closer; a crease keeps them
    apart). ``anchor``: an on-surface point for each bracket (e.g. its centre)
    towards which an end on a flat field moves first (see :meth:`Surface.project`); trial
    points use the first end. ``ends``: the ends already projected (:meth:`Surface.ends`;
    A, B and anchor are then unused).

    ``finish`` (per bracket, or one for all): a crease bracket narrower than this
    stops, and its crossing is the point where its ends' tangent planes meet,
    projected onto the surface. That point is off the crease by about the sheets'
    curvature times the width squared: with ``finish`` = sqrt(tol * L) for sheets
    curved no tighter than radius L, by about ``tol``. The plain iterations crawl
    down there (an estimate next to one end moves that end by its nudge alone), so
    this saves a crease's last several bisections, tiny batches each. Where there
    is no such point to trust, the bracket is bisected on down to ``tol``.

    Returns the seven arrays above and the rows left open. With ``pause``, a bracket
    still narrowing after ``iters`` iterations is left open (and not valid) with its
    narrowed ends, for the caller to go on from later (a batch runs as long as its
    slowest bracket: MASSRIS agents act once per system iteration); otherwise it
    is not valid."""
    if ends is None:
        ends = surface.ends(kinds, A, B, ref, anchor)
    A, gA, sA, B, gB, sB = (x.copy() for x in ends)
    offA = np.zeros(len(A), bool)           # A is a trial point not yet projected to the end
    valid = (sA > 0) != (sB > 0)
    jump = kinds == CREASE
    last = np.zeros(len(A), np.int8)        # which end moved last (Illinois)
    width = np.linalg.norm(A - B, axis=1)
    stalls = np.zeros(len(A), np.int64)
    estimate_ok = np.ones(len(A), bool)    # a crease bracket may use the estimate next
    estimated = np.zeros(len(A), bool)
    live = np.flatnonzero(valid)
    check = width.copy()                     # width at the last progress check
    check_c = width.copy()                   # the same for crease brackets
    width0 = width.copy()
    stop_c = np.maximum(np.broadcast_to(tol if finish is None else finish, (len(A),)), tol)
    for it in range(iters):
        if len(live) == 0:
            break
        w = np.linalg.norm(A[live] - B[live], axis=1)
        # the crease estimate again unless the last one left the bracket above 0.7 of its width
        estimate_ok[live] = ~estimated[live] | (w <= 0.7 * width[live])
        # a crease bracket whose trial points keep projecting back onto its ends (the
        # segment leaves the surface: no crease between them) stops, invalid
        stalls[live] = np.where(w > 0.9 * width[live], stalls[live] + 1, 0)
        width[live] = w
        dead = jump[live] & (stalls[live] >= 3)
        if it and it % PROGRESS_EVERY == 0:
            # a smooth bracket not down to a quarter in PROGRESS_EVERY iterations is
            # not converging (its ends jump between surface sheets): it stops, invalid
            # (a crease bracket that cannot narrow still hands its ends to the
            # caller, which bisects again with the ends' own side normals)
            dead |= ~jump[live] & (w > 0.25 * check[live])
            check[live] = w
        if it and it % PROGRESS_EVERY == 0:
            # a crease bracket gets twice as long (trial points landing off the
            # segment could otherwise keep it oscillating for all its iterations)
            dead |= jump[live] & (w > 0.25 * check_c[live])
            check_c[live] = w
        if crease_angle is not None:
            jl = np.flatnonzero(jump[live] & ~dead)
            if len(jl):
                j = live[jl]
                cos = np.einsum("ij,ij->i", surface.normals(gA[j]), surface.normals(gB[j]))
                dead[jl[cos > np.cos(0.5 * crease_angle)]] = True
            # and the converse: a smooth crossing (n.v, curvature) whose ends' normals
            # are still apart by half the crease angle once the bracket is down to a
            # hundredth, and whose signed quantity is still far from zero at both
            # ends, jumps across a crease (where n.v jumps through zero); the caller
            # would reject it at the end, after every remaining iteration. Where n.v
            # is small beside the crease, it does so too once the bracket is down to
            # a thousandth (a smooth sheet would have to bend through half the crease
            # angle within that: a radius of curvature below a thousandth of a cell)
            sl = np.flatnonzero(~jump[live] & ~dead & (w < 0.01 * width0[live]))
            if len(sl):
                j = live[sl]
                cos = np.einsum("ij,ij->i", surface.normals(gA[j]), surface.normals(gB[j]))
                far = np.minimum(np.abs(surface.signs(kinds[j], A[j], gA[j], ref[j])),
                                 np.abs(surface.signs(kinds[j], B[j], gB[j], ref[j])))
                scale = np.where(np.isin(kinds[j], CURVED), surface.scale, 1.0)
                tiny = w[sl] < 1e-3 * width0[j]
                dead[sl[(cos < np.cos(0.5 * crease_angle)) & ((far * scale > 0.05) | tiny)]] = True
        valid[live[dead]] = False
        live, w = live[~dead], w[~dead]
        live = live[w > np.where(jump[live], stop_c[live], tol)]
        if len(live) == 0:
            break
        a, b = sA[live], sB[live]
        u = np.where(jump[live], 0.5, a / np.where(a - b == 0, 1.0, a - b))
        u = np.clip(u, 0.02, 0.98)
        trial = A[live] + u[:, None] * (B[live] - A[live])
        jl = np.flatnonzero(jump[live])
        extra = trial[:0]
        if len(jl):
            # a crease: the estimate from the two tangent planes, nudged a little
            # towards each end, two trial points (one per side, one batch); after
            # an estimate that left the bracket above 0.7 of its width (off by more
            # than the small nudge: sheets curved at the bracket's scale), by a
            # quarter of the width
            j = live[jl]
            X = crease_estimate(A[j], B[j], surface.normals(gA[j]), surface.normals(gB[j]), trial[jl])
            estimated[live] = False
            estimated[j] = estimate_ok[j]
            nudge = np.where(estimate_ok[j], CREASE_NUDGE, WIDE_NUDGE)
            eps = nudge[:, None] * np.linalg.norm(B[j] - A[j], axis=1)[:, None]
            trial[jl] = X + eps * unit(A[j] - X)
            extra = X + eps * unit(B[j] - X)
        m = len(trial)
        # trial points two Newton steps towards the surface (the chord between two
        # surface points strays from it by the curvature times the width squared, so
        # a wide bracket's land within about 1e-6 of a cell, a narrow one's to
        # rounding): plenty for the sign of their quantity; a crossing left on such a
        # point is projected the rest of the way at the end (offA)
        rows = np.concatenate([live, live[jl]])
        M, fM, gM = surface.project(np.concatenate([trial, extra]), steps=2,
                                    anchor=np.concatenate([A[live], A[live[jl]]]))
        sM = surface.signs(kinds[rows], M, gM, ref[rows])
        # a crease trial point whose projection did not settle near the surface (near
        # a sharp wedge's edge Newton can stall between the sheets) moves no end
        on = on_surface(fM, surface.iso, TRIAL)
        exact = on_surface(fM, surface.iso, CONVERGED)
        M2, gM2, sM2, rows2, on2, exact2 = M[m:], gM[m:], sM[m:], rows[m:], on[m:], exact[m:]
        M, gM, sM, on, exact = M[:m], gM[:m], sM[:m], on[:m], exact[:m]
        # a smooth crossing is found when its signed quantity vanishes (ZERO_SIGN;
        # n.v is a cosine, a curvature is scaled by the model's size)
        hit = ~jump[live] & (np.abs(sM) * np.where(np.isin(kinds[live], CURVED), surface.scale, 1.0) < ZERO_SIGN)
        if hit.any():
            ih = live[hit]
            A[ih], gA[ih], B[ih], gB[ih] = M[hit], gM[hit], M[hit], gM[hit]
            offA[ih] = ~exact[hit]
            keep = ~hit
            live, M, gM, sM, on, exact = live[keep], M[keep], gM[keep], sM[keep], on[keep], exact[keep]
            if len(live) == 0:
                break
        moves = on | ~jump[live]
        sideA = (sM > 0) == (sA[live] > 0)
        ia, ib = live[sideA & moves], live[~sideA & moves]
        A[ia], gA[ia], sA[ia] = M[sideA & moves], gM[sideA & moves], sM[sideA & moves]
        offA[ia] = ~exact[sideA & moves]
        B[ib], gB[ib], sB[ib] = M[~sideA & moves], gM[~sideA & moves], sM[~sideA & moves]
        if len(rows2):
            # the second trial point: it replaces the end of its side where it narrows the bracket
            sa2 = (sM2 > 0) == (sA[rows2] > 0)
            wide = np.linalg.norm(A[rows2] - B[rows2], axis=1)
            narrowA = on2 & sa2 & (np.linalg.norm(M2 - B[rows2], axis=1) < wide)
            narrowB = on2 & ~sa2 & (np.linalg.norm(M2 - A[rows2], axis=1) < wide)
            ra, rb = rows2[narrowA], rows2[narrowB]
            A[ra], gA[ra], sA[ra] = M2[narrowA], gM2[narrowA], sM2[narrowA]
            offA[ra] = ~exact2[narrowA]
            B[rb], gB[rb], sB[rb] = M2[narrowB], gM2[narrowB], sM2[narrowB]
        # Illinois: halve the stale end's value when the same end moves twice
        sB[ia[last[ia] == 1]] *= 0.5
        sA[ib[last[ib] == 2]] *= 0.5
        last[ia], last[ib] = 1, 2
    else:                                    # out of iterations: unconverged smooth ones are invalid
        if len(live):
            open_ = (np.linalg.norm(A[live] - B[live], axis=1) > tol) & ~jump[live]
            valid[live[open_]] = False
    paused = np.zeros(len(A), bool)
    if pause and len(live):
        w = np.linalg.norm(A[live] - B[live], axis=1)
        live = live[w > np.where(jump[live], stop_c[live], tol)]     # the last iteration's converged ones are done
        paused[live] = True
        valid[live] = False
    X, gX = A.copy(), gA.copy()
    off = np.flatnonzero(offA & valid)
    if len(off):
        X[off], _, gX[off] = surface.project(X[off])        # the crossings onto the surface to the end
    if finish is not None:
        rest = _finish_creases(surface, np.flatnonzero(jump & valid), A, gA, B, gB, tol, X, gX)
        if len(rest):
            # no tangent-plane point to trust there: bisected on down to tol
            ends = (A[rest], gA[rest], surface.signs(kinds[rest], A[rest], gA[rest], ref[rest]),
                    B[rest], gB[rest], surface.signs(kinds[rest], B[rest], gB[rest], ref[rest]))
            out, more = bisect_some(surface, kinds[rest], None, None, ref[rest], tol, iters, crease_angle, ends=ends,
                                    pause=pause)
            for arr, val in zip((X, gX, A, B, valid, paused), (out[0], out[1], out[2], out[3], out[6], more)):
                arr[rest] = val
    return (X, gX, A, B, surface.normals(gA), surface.normals(gB), valid), paused


def _finish_creases(surface, rows, A, gA, B, gB, tol, X, gX):
    """Crease crossings (X, gX, in place) of narrow brackets still wider than tol:
    where the ends' tangent planes meet, projected onto the surface (across a sharp
    wedge up to WEDGE widths from the bracket's midpoint). Returns the rows where
    there is no such point (parallel planes, or meeting too far off) or its
    projection moves further than the bracket is wide."""
    w = np.linalg.norm(A[rows] - B[rows], axis=1)
    rows, w = rows[w > tol], w[w > tol]
    if len(rows) == 0:
        return rows
    mid = 0.5 * (A[rows] + B[rows])
    E, ok = crease_estimate(A[rows], B[rows], surface.normals(gA[rows]), surface.normals(gB[rows]), mid, planes=True)
    P, f, g = surface.project(E.copy(), steps=4, max_step=float(w.max()))
    ok &= (np.linalg.norm(P - E, axis=1) <= w) & (np.linalg.norm(P - mid, axis=1) <= WEDGE * w)
    ok &= on_surface(f, surface.iso)
    X[rows[ok]], gX[rows[ok]] = P[ok], g[ok]
    return rows[~ok]
