"""Batched surface queries shared by all agents: projection onto the iso-surface,
normals, and the signed quantities whose zero sets are the feature outlines.

Kinds (the order of blackboard.board.FEATURE_KINDS): 0 silhouette, where the outward
normal is perpendicular to the direction to the eye; 1 crease, where the normal jumps
(signed against the two side normals of the bracket: ``ref = n_a - n_b``); 2 curvature
sign, where the mean curvature changes sign; 3 suggestive contour (DeCarlo et al. 2003),
where the radial curvature (model.curvature.radial: the surface's curvature along the
view direction projected onto it) changes sign, growing towards the eye.
"""
import numpy as np

from ..model.curvature import along_points, along_values, curvature, radial
from ..model.projection import newton
from ..model.vectors import cross
from .asks import Ask, run
from .steering import unit

SIL, CREASE, CURV, SUG = 0, 1, 2, 3
CURVED = (CURV, SUG)         # kinds whose signed quantity is a curvature (scaled by the model's size)
MARCH = 16                   # samples towards the anchor for a point on a flat field
NEWTON_ITERS = 6             # Newton iterations of a silhouette corrector before it gives up
WEDGE = 3.0                  # a crease estimate may lie this many bracket widths from its midpoint
# a curvature-sign line is drawn only where the surface really turns from convex to concave:
FLAT = 2.0                   # ... curved: |k1| + |k2| at least this over the model's size (flatter is noise)
ZERO_MEAN = 0.02             # ... on the zero: |k1 + k2| at most this share of |k1| + |k2| (more: a jump of
                             # the curvature, where a field's pieces meet, not a zero of it)
CROSSES = 0.005              # ... and across it: the mean curvature over |k1| + |k2| at PROBE to either side
PROBE = 0.01                 # of the line (a share of the model's size) has opposite signs, each at least
                             # CROSSES (a twisted face, a helicoid, has zero mean curvature all over)
# a suggestive contour is drawn where it is one (DeCarlo et al. 2003) and shows: on a curved part (FLAT)
# facing the eye, the view not head on (|w|, the view direction's part in the tangent plane, at least
# OBLIQUE), and the radial curvature over |k1| + |k2| at PROBE to either side along w is at least CROSSES
# towards the eye and at most -CROSSES away from it (its derivative along w is positive)
OBLIQUE = 0.1


class Surface:
    def __init__(self, ev, view):
        self.ev = ev
        self.iso = ev.iso
        self.view = view
        self.scale = ev.scale

    def field_grad(self, P):
        return self.ev.field_grad(P)

    def project(self, P, steps=8, max_step=None, anchor=None, anchor_rows=None):
        """Damped Newton steps along the gradient onto f = iso (model.projection; at most
        ``steps`` field evaluations after the first). Returns P, f, g.

        A point where the field is flat (no gradient: empty space, or the core of a
        primitive or of a subtracted one) has no direction to follow; with ``anchor``
        (a nearby point on the surface for each point) it first moves towards its
        anchor, to the first of MARCH samples where the field has a gradient. With
        ``anchor_rows`` (-1: none) the anchor of a point is the projection of another
        point of the same batch: those come out of one batch of Newton steps, and the
        flat points march towards them and take their Newton steps after."""
        P = np.array(P, float)
        if len(P) == 0:
            return P, np.zeros(0), np.zeros((0, 3))
        max_step = max_step if max_step is not None else 0.05 * self.scale
        f, g = self.ev.field_grad(P)
        flat = ()
        if anchor is not None or anchor_rows is not None:
            flat = np.flatnonzero(~(np.einsum("ij,ij->i", g, g) > 1e-300))
        if anchor is not None and len(flat):
            self._march(P, f, g, flat, np.asarray(anchor, float)[flat])
        newton(self.ev, P, f, g, steps, max_step)
        if anchor_rows is not None and len(flat):
            flat = flat[anchor_rows[flat] >= 0]
            if len(flat):
                # flat points stayed put in the Newton steps above
                Pf, ff, gf = P[flat], f[flat], g[flat]
                self._march(Pf, ff, gf, np.arange(len(flat)), P[anchor_rows[flat]])
                newton(self.ev, Pf, ff, gf, steps, max_step)
                P[flat], f[flat], g[flat] = Pf, ff, gf
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

    def silhouette_newton(self, Q, T, reach, tol, back=None):
        """:meth:`silhouette_newton_steps` run alone."""
        return run(self.ev, self.silhouette_newton_steps(Q, T, reach, tol, back))[0]

    def silhouette_newton_steps(self, Q, T, reach, tol, back=None):
        """Silhouette points by Newton's method on {f = iso, grad f . v = 0, (x - Q) . T = 0}:
        on the surface, on the silhouette, in the plane through each predicted point Q
        across its tangent T (v: towards the eye, unnormalised for a perspective view).
        Each iteration is one batched evaluation of field and gradient at the points
        and a little along v (the Jacobian's row of grad f . v needs the Hessian times
        v alone: model.curvature.field_grad_along, two points per point). Returns X,
        the field and gradient of the last evaluation, the silhouette's tangent there
        (grad f x grad(grad f . v), turned along T: the next step's direction), whether
        each point converged (the last step below ``tol``) without a singular system (a
        cusp, a fold of the silhouette) or moving further than ``reach`` from Q (a seed's
        refinement bisects the others, a trace retries them shorter), and, given
        ``back`` (a point per row), the Hessian times (X - back) at the converged
        points, else None: one more evaluation at each converged X and a little towards
        back (the gradient at ``back`` predicted from X is the gradient less that), whose
        field and gradient at X itself are then the ones returned (a trace step needs
        them at its new point). A solver (agents.asks): a generator of its evaluations."""
        X = np.array(Q, float)
        m = len(X)
        reach = np.broadcast_to(reach, (m,))
        F, G, Tout = np.zeros(m), np.zeros((m, 3)), np.array(T, float)
        ok = np.zeros(m, bool)
        live = np.arange(m)
        for _ in range(NEWTON_ITERS):
            if len(live) == 0:
                break
            x = X[live]
            if self.view.eye is not None:
                w = self.view.eye - x
            else:
                w = np.broadcast_to(-self.view.direction, x.shape)
            batch, L, step = along_points(self.ev, x, [w])
            f, g, hd = along_values(*(yield Ask(batch)), L, step)
            F[live], G[live] = f, g
            ds = hd[0] - g if self.view.eye is not None else hd[0]
            Tl = T[live]
            tan = unit(cross(g, ds))
            Tout[live] = np.where(np.einsum("ij,ij->i", tan, Tl)[:, None] < 0, -tan, tan)
            J = np.stack([g, ds, Tl], axis=1)                                  # (k, 3, 3)
            r = -np.stack([f - self.iso, np.einsum("ij,ij->i", g, w),
                           np.einsum("ij,ij->i", x - Q[live], Tl)], axis=1)
            # (near) singular: the silhouette turns along the view (a cusp), or the gradient vanishes
            live = newton_update(X, Q, live, J, r, reach, tol, ok)
        bend = None
        if back is not None:
            bend = np.zeros((m, 3))
            done = np.flatnonzero(ok)
            if len(done):
                batch, L, step = along_points(self.ev, X[done], [X[done] - back[done]])
                F[done], G[done], hd = along_values(*(yield Ask(batch)), L, step)
                bend[done] = hd[0]
        return X, F, G, Tout, ok, bend

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
        m = kinds == SUG
        if m.any():
            s[m] = radial(curvature(self.ev, P[m], g[m]), self.view.towards_eye(P[m]))[0]
        return s

    def curvature_crossings(self, X, g, T):
        """Whether points X (gradients g, line tangents T) of a curvature-sign line lie where
        the surface turns from convex to concave (FLAT, ZERO_MEAN, CROSSES): the line,
        not noise of a near-zero curvature on a flat or nearly flat part."""
        if len(X) == 0:
            return np.zeros(0, bool)
        m = len(X)
        c, here, _, _ = self.probed(X, g, unit(cross(self.normals(g), T)))
        mean = c["k1"] + c["k2"]
        return _crossing(mean, here, m, self.scale) & (np.abs(mean[:m]) <= ZERO_MEAN * here[:m])

    def suggestive_valid(self, X, g):
        """Whether points X (gradients g) of a zero of the radial curvature are suggestive
        contour points that show (FLAT, ZERO_MEAN, OBLIQUE, CROSSES): facing the eye, seen
        obliquely, on a zero (not a jump) of the radial curvature, which grows towards the
        eye across the line."""
        m = len(X)
        if m == 0:
            return np.zeros(0, bool)
        n, v = self.normals(g), self.view.towards_eye(X)
        w = v - np.einsum("ij,ij->i", v, n)[:, None] * n
        c, here, P, _ = self.probed(X, g, unit(w))          # + side: towards the eye
        kr = radial(c, self.view.towards_eye(np.concatenate([X, P])))[0]
        ok = _crossing(kr, here, m, self.scale, ordered=True) & (np.abs(kr[:m]) <= ZERO_MEAN * here[:m])
        return ok & (np.einsum("ij,ij->i", n, v) > 0) & (np.linalg.norm(w, axis=1) >= OBLIQUE)

    def probed(self, X, g, W, d=None, here=None):
        """The curvature at X and ``d`` (per point; default PROBE of the model's size) to
        either side along the unit directions W (projected onto the surface), one batch:
        the curvature dict over the 3m points, |k1| + |k2| there, and the probes with
        their gradients. ``here``: the curvature at X, when the caller has it (only the
        probes' is evaluated)."""
        d = (PROBE * self.scale if d is None else np.asarray(d, float)[:, None]) * W
        P, _, gP = self.project(np.concatenate([X + d, X - d]), anchor=np.concatenate([X, X]))
        if here is None:
            c = curvature(self.ev, np.concatenate([X, P]), np.concatenate([g, gP]))
        else:
            cP = curvature(self.ev, P, gP)
            c = {k: np.concatenate([here[k], cP[k]]) for k in cP}
        return c, np.abs(c["k1"]) + np.abs(c["k2"]), P, gP

    def ends(self, kinds, A, B, ref, anchor=None):
        """Bracket ends projected onto the surface, with their gradients and signed
        quantities: (A, gA, sA, B, gB, sB), as agents.bisection.bisect takes them."""
        m = len(A)
        anchor = None if anchor is None else np.concatenate([anchor, anchor])
        P, _, g = self.project(np.concatenate([A, B]), anchor=anchor)      # one batch
        s = self.signs(np.concatenate([kinds, kinds]), P, g, np.concatenate([ref, ref]))
        return P[:m], g[:m], s[:m], P[m:], g[m:], s[m:]


def _crossing(q, size, m, scale, ordered=False):
    """Whether a curvature quantity ``q`` (over 3m points: the m points, then the probes
    to the + side, then the - side; ``size``: |k1| + |k2| there) crosses zero at each
    point: the point is curved (FLAT, against the model's size), the probes' q over size
    have opposite signs, each at least CROSSES (``ordered``: the + side's positive)."""
    rel = q / np.where(size > 0, size, 1.0)
    plus, minus = rel[m:2 * m], rel[2 * m:]
    ok = plus >= CROSSES if ordered else (plus * minus < 0)
    ok &= (minus <= -CROSSES) if ordered else (np.minimum(np.abs(plus), np.abs(minus)) >= CROSSES)
    return ok & (size[:m] * scale >= FLAT) & np.isfinite(size[:m])


def newton_update(X, Q, live, J, r, reach, tol, ok):
    """One damped Newton step J dx = r (J: (k, 3, 3)) for the rows ``live`` of X, in
    place: no step longer than half the row's reach. A row whose step was below tol is
    done (``ok``, in place); one whose system is (near) singular (a scale-free test on
    the rows' lengths), or that went further than its reach from Q, gives up. Returns
    the rows still live."""
    # Cramer's rule: the inverse's columns are the cross products of J's rows over
    # det (LAPACK's batched det and solve cost more than the sum on tiny batches)
    r0, r1, r2 = J[:, 0], J[:, 1], J[:, 2]
    c0, c1, c2 = cross(r1, r2), cross(r2, r0), cross(r0, r1)
    det = np.einsum("ij,ij->i", r0, c0)
    size = np.sqrt(np.einsum("ikj,ikj->ik", J, J).prod(axis=1))
    good = np.isfinite(det) & (np.abs(det) > 1e-6 * size)
    inv = np.where(good, 1.0 / np.where(good, det, 1.0), 0.0)[:, None]
    dx = (r[:, :1] * c0 + r[:, 1:2] * c1 + r[:, 2:3] * c2) * inv
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
