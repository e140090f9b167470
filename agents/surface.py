"""Batched surface queries shared by all agents: projection onto the iso-surface,
normals, and the signed quantities whose zero sets are the feature outlines.

Kinds (the order of blackboard.board.FEATURE_KINDS): 0 silhouette, where the outward
normal is perpendicular to the direction to the eye; 1 crease, where the normal jumps
(signed against the two side normals of the bracket: ``ref = n_a - n_b``); 2 curvature
sign, where the mean curvature changes sign.
"""
import numpy as np

from ..model.curvature import curvature, field_grad_hessian
from ..model.projection import newton

SIL, CREASE, CURV = 0, 1, 2
CREASE_NUDGE = 0.05          # crease trial points step this fraction of the bracket off the estimate
WIDE_NUDGE = 0.25            # ... and this much after an estimate that left the bracket above 0.7
MARCH = 16                   # samples towards the anchor for a point on a flat field
PROGRESS_EVERY = 6           # bisection iterations within which a bracket must shrink to a quarter
NEWTON_ITERS = 6             # Newton iterations of a silhouette corrector before it gives up
WEDGE = 3.0                  # a crease estimate may lie this many bracket widths from its midpoint


def unit(v):
    return v / np.maximum(np.linalg.norm(v, axis=-1, keepdims=True), 1e-300)


class Surface:
    def __init__(self, ev, view):
        self.ev = ev
        self.iso = ev.iso
        self.view = view
        self.scale = ev.scale

    def field_grad(self, P):
        return self.ev.field_grad(P)

    def project(self, P, steps=8, max_step=None, anchor=None):
        """Damped Newton steps along the gradient onto f = iso (model.projection; at most
        ``steps`` field evaluations after the first). Returns P, f, g.

        A point where the field is flat (no gradient: empty space, or the core of a
        primitive or of a subtracted one) has no direction to follow; with ``anchor``
        (a nearby point on the surface for each point) it first moves towards its
        anchor, to the first of MARCH samples where the field has a gradient."""
        P = np.array(P, float)
        if len(P) == 0:
            return P, np.zeros(0), np.zeros((0, 3))
        max_step = max_step if max_step is not None else 0.05 * self.scale
        f, g = self.ev.field_grad(P)
        if anchor is not None:
            flat = np.flatnonzero(~(np.einsum("ij,ij->i", g, g) > 1e-300))
            if len(flat):
                self._march(P, f, g, flat, np.asarray(anchor, float)[flat])
        newton(self.ev, P, f, g, steps, max_step)
        return P, f, g

    def _march(self, P, f, g, rows, anchor):
        """Move P[rows] (in place, with f and g) off a flat field: towards their anchors
        to the first of MARCH samples where the gradient does not vanish, then along
        that gradient (uphill when outside, downhill when inside) to the first sign
        change of f - iso within twice the anchor distance, located by linear
        interpolation (Newton then finishes; a tiny gradient near a flat core would
        throw a Newton step far away)."""
        t = np.arange(1, MARCH + 1) / MARCH
        P0 = P[rows]
        reach = 2.0 * np.linalg.norm(anchor - P0, axis=1)
        S = P0[:, None, :] + t[None, :, None] * (anchor - P0)[:, None, :]
        fs, gs = self.ev.field_grad(S.reshape(-1, 3))
        fs, gs = fs.reshape(len(rows), MARCH), gs.reshape(len(rows), MARCH, 3)
        good = np.einsum("ijk,ijk->ij", gs, gs) > 1e-300
        has = np.flatnonzero(good.any(axis=1))
        if len(has) == 0:
            return
        first = np.argmax(good[has], axis=1)
        Pm, fm, gm = S[has, first], fs[has, first], gs[has, first]
        up = np.where(fm < self.iso, 1.0, -1.0)
        d = up[:, None] * gm / np.linalg.norm(gm, axis=1, keepdims=True)
        tt = reach[has, None] * t[None, :]                                   # (k, MARCH)
        R = Pm[:, None, :] + tt[:, :, None] * d[:, None, :]
        fr = self.ev.field(R.reshape(-1, 3)).reshape(len(has), MARCH)
        fr = np.concatenate([fm[:, None], fr], axis=1) - self.iso            # t = 0 first
        tt = np.concatenate([np.zeros((len(has), 1)), tt], axis=1)
        flip = (fr[:, 1:] > 0) != (fr[:, :1] > 0)
        hit = flip.any(axis=1)
        j = np.argmax(flip, axis=1)
        k = np.arange(len(has))
        f0, f1 = fr[k, j], fr[k, j + 1]
        u = np.where(f1 != f0, f0 / np.where(f1 != f0, f0 - f1, 1.0), 0.0)
        tc = tt[k, j] + np.clip(u, 0.0, 1.0) * (tt[k, j + 1] - tt[k, j])
        Pn = np.where(hit[:, None], Pm + tc[:, None] * d, Pm)
        fn, gn = self.ev.field_grad(Pn)
        P[rows[has]], f[rows[has]], g[rows[has]] = Pn, fn, gn

    def silhouette_newton(self, Q, T, reach, tol):
        """Silhouette points by Newton's method on {f = iso, grad f . v = 0, (x - Q) . T = 0}:
        on the surface, on the silhouette, in the plane through each predicted point Q
        across its tangent T (v: towards the eye, unnormalised for a perspective view).
        Each iteration is one batched evaluation of field, gradient and Hessian (the
        Hessian by forward differences of the analytic gradient: four points per point).
        Returns X, the gradient and Hessian of its last iteration, the silhouette's
        tangent there (grad f x grad(grad f . v), turned along T: the next step's
        direction), and whether each point converged (the last step below ``tol``)
        without a singular system (a cusp, a fold of the silhouette) or moving further
        than ``reach`` from Q; the caller falls back to bracketing for the others."""
        X = np.array(Q, float)
        m = len(X)
        reach = np.broadcast_to(reach, (m,))
        G, H, Tout = np.zeros((m, 3)), np.zeros((m, 3, 3)), np.array(T, float)
        ok = np.zeros(m, bool)
        live = np.arange(m)
        for _ in range(NEWTON_ITERS):
            if len(live) == 0:
                break
            x = X[live]
            f, g, h = field_grad_hessian(self.ev, x, forward=True)
            G[live], H[live] = g, h
            if self.view.eye is not None:
                w = self.view.eye - x
                ds = np.einsum("nij,nj->ni", h, w) - g
            else:
                w = np.broadcast_to(-self.view.direction, x.shape)
                ds = np.einsum("nij,nj->ni", h, w)
            Tl = T[live]
            tan = unit(np.cross(g, ds))
            Tout[live] = np.where(np.einsum("ij,ij->i", tan, Tl)[:, None] < 0, -tan, tan)
            J = np.stack([g, ds, Tl], axis=1)                                  # (k, 3, 3)
            r = -np.stack([f - self.iso, np.einsum("ij,ij->i", g, w),
                           np.einsum("ij,ij->i", x - Q[live], Tl)], axis=1)
            # (near) singular: the silhouette turns along the view (a cusp), or the gradient vanishes
            live = newton_update(X, Q, live, J, r, reach, tol, ok)
        return X, G, H, Tout, ok

    @staticmethod
    def normals(g):
        n = -g / np.maximum(np.linalg.norm(g, axis=1, keepdims=True), 1e-300)
        return n

    def signs(self, kinds, P, g, ref):
        """The signed quantity of each point's feature kind."""
        n = self.normals(g)
        s = np.empty(len(P))
        m = kinds == SIL
        if m.any():
            s[m] = np.einsum("ij,ij->i", n[m], self.view.towards_eye(P[m]))
        m = kinds == CREASE
        if m.any():
            s[m] = np.einsum("ij,ij->i", n[m], ref[m])
        m = kinds == CURV
        if m.any():
            s[m] = curvature(self.ev, P[m], g[m])["mean"]
        return s

    def ends(self, kinds, A, B, ref, anchor=None):
        """Bracket ends projected onto the surface, with their gradients and signed
        quantities: (A, gA, sA, B, gB, sB), as :meth:`bisect` takes them."""
        m = len(A)
        anchor = None if anchor is None else np.concatenate([anchor, anchor])
        P, _, g = self.project(np.concatenate([A, B]), anchor=anchor)      # one batch
        s = self.signs(np.concatenate([kinds, kinds]), P, g, np.concatenate([ref, ref]))
        return P[:m], g[:m], s[:m], P[m:], g[m:], s[m:]

    def bisect(self, kinds, A, B, ref, tol, iters=60, crease_angle=None, anchor=None, ends=None, finish=None):
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
        widen a bracket across a sharp wedge). A crease trial point whose projection
        does not settle on the surface moves no end. Returns the crossing (the
        final bracket end on the first end's side, on the surface to rounding), its
        gradient, the final bracket ends and their normals, and whether each bracket
        held a sign change. With ``crease_angle``, a crease bracket whose end normals
        come within half of it is a smooth bend, not a crease: it stops at once, invalid
        (narrowing a smooth surface only brings the normals closer; a crease keeps them
        apart). ``anchor``: an on-surface point for each bracket (e.g. its centre)
        towards which an end on a flat field moves first (see :meth:`project`); trial
        points use the first end. ``ends``: the ends already projected (:meth:`ends`;
        A, B and anchor are then unused).

        ``finish`` (per bracket, or one for all): a crease bracket narrower than this
        stops, and its crossing is the point where its ends' tangent planes meet,
        projected onto the surface. That point is off the crease by about the sheets'
        curvature times the width squared: with ``finish`` = sqrt(tol * L) for sheets
        curved no tighter than radius L, by about ``tol``. The plain iterations crawl
        down there (an estimate next to one end moves that end by its nudge alone), so
        this saves a crease's last several bisections, tiny batches each. Where there
        is no such point to trust, the bracket is bisected on down to ``tol``."""
        if ends is None:
            ends = self.ends(kinds, A, B, ref, anchor)
        A, gA, sA, B, gB, sB = (x.copy() for x in ends)
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
                # a crease bracket gets twice as long (it used to oscillate for all 60
                # iterations between trial points landing off the segment)
                dead |= jump[live] & (w > 0.25 * check_c[live])
                check_c[live] = w
            if crease_angle is not None:
                jl = np.flatnonzero(jump[live] & ~dead)
                if len(jl):
                    j = live[jl]
                    cos = np.einsum("ij,ij->i", self.normals(gA[j]), self.normals(gB[j]))
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
                    cos = np.einsum("ij,ij->i", self.normals(gA[j]), self.normals(gB[j]))
                    far = np.minimum(np.abs(self.signs(kinds[j], A[j], gA[j], ref[j])),
                                     np.abs(self.signs(kinds[j], B[j], gB[j], ref[j])))
                    scale = np.where(kinds[j] == CURV, self.scale, 1.0)
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
                X = crease_estimate(A[j], B[j], self.normals(gA[j]), self.normals(gB[j]), trial[jl])
                estimated[live] = False
                estimated[j] = estimate_ok[j]
                nudge = np.where(estimate_ok[j], CREASE_NUDGE, WIDE_NUDGE)
                eps = nudge[:, None] * np.linalg.norm(B[j] - A[j], axis=1)[:, None]
                trial[jl] = X + eps * unit(A[j] - X)
                extra = X + eps * unit(B[j] - X)
            m = len(trial)
            M, fM, gM = self.project(np.concatenate([trial, extra]), steps=4,
                                     anchor=np.concatenate([A[live], A[live[jl]]]))
            rows = np.concatenate([live, live[jl]])
            sM = self.signs(kinds[rows], M, gM, ref[rows])
            # a crease trial point whose projection did not settle on the surface (near a
            # sharp wedge's edge Newton can stall between the sheets) moves no end
            on = np.abs(fM - self.iso) <= 1e-12 * max(self.iso, 1.0)
            M2, gM2, sM2, rows2, on2 = M[m:], gM[m:], sM[m:], rows[m:], on[m:]
            M, gM, sM, on = M[:m], gM[:m], sM[:m], on[:m]
            # a smooth crossing is found when its signed quantity vanishes (to 1e-11;
            # n.v is a cosine, mean curvature is scaled by the model's size)
            hit = ~jump[live] & (np.abs(sM) * np.where(kinds[live] == CURV, self.scale, 1.0) < 1e-11)
            if hit.any():
                ih = live[hit]
                A[ih], gA[ih], B[ih], gB[ih] = M[hit], gM[hit], M[hit], gM[hit]
                keep = ~hit
                live, M, gM, sM, on = live[keep], M[keep], gM[keep], sM[keep], on[keep]
                if len(live) == 0:
                    break
            moves = on | ~jump[live]
            sideA = (sM > 0) == (sA[live] > 0)
            ia, ib = live[sideA & moves], live[~sideA & moves]
            A[ia], gA[ia], sA[ia] = M[sideA & moves], gM[sideA & moves], sM[sideA & moves]
            B[ib], gB[ib], sB[ib] = M[~sideA & moves], gM[~sideA & moves], sM[~sideA & moves]
            if len(rows2):
                # the second trial point: it replaces the end of its side where it narrows the bracket
                sa2 = (sM2 > 0) == (sA[rows2] > 0)
                wide = np.linalg.norm(A[rows2] - B[rows2], axis=1)
                narrowA = on2 & sa2 & (np.linalg.norm(M2 - B[rows2], axis=1) < wide)
                narrowB = on2 & ~sa2 & (np.linalg.norm(M2 - A[rows2], axis=1) < wide)
                ra, rb = rows2[narrowA], rows2[narrowB]
                A[ra], gA[ra], sA[ra] = M2[narrowA], gM2[narrowA], sM2[narrowA]
                B[rb], gB[rb], sB[rb] = M2[narrowB], gM2[narrowB], sM2[narrowB]
            # Illinois: halve the stale end's value when the same end moves twice
            sB[ia[last[ia] == 1]] *= 0.5
            sA[ib[last[ib] == 2]] *= 0.5
            last[ia], last[ib] = 1, 2
        else:                                    # out of iterations: unconverged smooth ones are invalid
            if len(live):
                open_ = (np.linalg.norm(A[live] - B[live], axis=1) > tol) & ~jump[live]
                valid[live[open_]] = False
        X, gX = A.copy(), gA.copy()
        if finish is not None:
            rest = self._finish_creases(np.flatnonzero(jump & valid), A, gA, B, gB, tol, X, gX)
            if len(rest):
                # no tangent-plane point to trust there: bisected on down to tol
                ends = (A[rest], gA[rest], self.signs(kinds[rest], A[rest], gA[rest], ref[rest]),
                        B[rest], gB[rest], self.signs(kinds[rest], B[rest], gB[rest], ref[rest]))
                out = self.bisect(kinds[rest], None, None, ref[rest], tol, iters, crease_angle, ends=ends)
                for arr, val in zip((X, gX, A, B, valid), (out[0], out[1], out[2], out[3], out[6])):
                    arr[rest] = val
        return X, gX, A, B, self.normals(gA), self.normals(gB), valid

    def _finish_creases(self, rows, A, gA, B, gB, tol, X, gX):
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
        E, ok = crease_estimate(A[rows], B[rows], self.normals(gA[rows]), self.normals(gB[rows]), mid, planes=True)
        P, f, g = self.project(E.copy(), steps=4, max_step=float(w.max()))
        ok &= (np.linalg.norm(P - E, axis=1) <= w) & (np.linalg.norm(P - mid, axis=1) <= WEDGE * w)
        ok &= np.abs(f - self.iso) <= 1e-12 * max(self.iso, 1.0)
        X[rows[ok]], gX[rows[ok]] = P[ok], g[ok]
        return rows[~ok]


def newton_update(X, Q, live, J, r, reach, tol, ok):
    """One damped Newton step J dx = r (J: (k, 3, 3)) for the rows ``live`` of X, in
    place: no step longer than half the row's reach. A row whose step was below tol is
    done (``ok``, in place); one whose system is (near) singular (a scale-free test on
    the rows' lengths), or that went further than its reach from Q, gives up. Returns
    the rows still live."""
    det = np.linalg.det(J)
    size = np.prod(np.linalg.norm(J, axis=2), axis=1)
    good = np.isfinite(det) & (np.abs(det) > 1e-6 * size)
    dx = np.zeros((len(live), 3))
    if good.any():
        dx[good] = np.linalg.solve(J[good], r[good][:, :, None])[:, :, 0]
    step = np.linalg.norm(dx, axis=1)
    lim = 0.5 * reach[live]
    dx *= np.where(step > lim, lim / np.maximum(step, 1e-300), 1.0)[:, None]
    X[live] += dx
    far = np.linalg.norm(X[live] - Q[live], axis=1) > reach[live]
    done = good & (step <= tol) & ~far
    ok[live[done]] = True
    return live[good & ~done & ~far & np.isfinite(step)]


def crease_estimate(A, B, nA, nB, mid, planes=False):
    """The point of the line where the ends' tangent planes meet that is nearest to the
    bracket's midpoint (on curved sheets it is off the crease by the square of the
    bracket's width); the midpoint where the planes are near parallel or the point is
    further from the midpoint than WEDGE bracket widths (across a sharp wedge, a hole's
    rim, the planes meet beyond both ends). With ``planes``: the planes' point and
    whether it is one (not the midpoint's fallback)."""
    c = np.einsum("ij,ij->i", nA, nB)
    det = 1.0 - c * c
    ra = np.einsum("ij,ij->i", nA, A - mid)
    rb = np.einsum("ij,ij->i", nB, B - mid)
    ok = det > 1e-6
    d = np.where(ok, det, 1.0)
    al = (ra - c * rb) / d
    be = (rb - c * ra) / d
    X = mid + al[:, None] * nA + be[:, None] * nB
    far = np.linalg.norm(X - mid, axis=1) > WEDGE * np.linalg.norm(B - A, axis=1)
    if planes:
        return X, ok & ~far
    return np.where((ok & ~far)[:, None], X, mid)
