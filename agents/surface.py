"""Batched surface queries shared by all agents: projection onto the iso-surface,
normals, and the signed quantities whose zero sets are the feature outlines.

Kinds (the order of blackboard.board.FEATURE_KINDS): 0 silhouette, where the outward
normal is perpendicular to the direction to the eye; 1 crease, where the normal jumps
(signed against the two side normals of the bracket: ``ref = n_a - n_b``); 2 curvature
sign, where the mean curvature changes sign.
"""
import numpy as np

from ..model.curvature import curvature

SIL, CREASE, CURV = 0, 1, 2
PROGRESS_EVERY = 6           # bisection iterations within which a bracket must shrink to a quarter


class Surface:
    def __init__(self, ev, view):
        self.ev = ev
        self.iso = ev.iso
        self.view = view
        self.scale = ev.scale

    def field_grad(self, P):
        return self.ev.field_grad(P)

    def project(self, P, steps=6, max_step=None):
        """Damped Newton steps along the gradient onto f = iso. Returns P, f, g."""
        P = np.array(P, float)
        if len(P) == 0:
            return P, np.zeros(0), np.zeros((0, 3))
        max_step = max_step if max_step is not None else 0.05 * self.scale
        f, g = self.ev.field_grad(P)
        tol = 1e-14 * max(1.0, self.iso)
        live = np.arange(len(P))
        for _ in range(steps):
            # only the points not yet on the surface are stepped (and evaluated)
            fl, gl = f[live], g[live]
            gg = np.einsum("ij,ij->i", gl, gl)
            ok = (gg > 1e-300) & (np.abs(fl - self.iso) > tol)
            live, fl, gl, gg = live[ok], fl[ok], gl[ok], gg[ok]
            if len(live) == 0:
                break
            d = -((fl - self.iso) / gg)[:, None] * gl
            L = np.linalg.norm(d, axis=1)
            d *= np.where(L > max_step, max_step / np.maximum(L, 1e-300), 1.0)[:, None]
            Q = P[live] + d
            fq, gq = self.ev.field_grad(Q)
            better = np.abs(fq - self.iso) <= np.abs(fl - self.iso)
            # where a full step overshoots, take half of it once
            worse = np.flatnonzero(~better)
            if len(worse):
                Q2 = P[live[worse]] + 0.5 * d[worse]
                f2, g2 = self.ev.field_grad(Q2)
                Q[worse], fq[worse], gq[worse] = Q2, f2, g2
                better[worse] = np.abs(f2 - self.iso) <= np.abs(fl[worse] - self.iso)
            moved = live[better]
            P[moved], f[moved], g[moved] = Q[better], fq[better], gq[better]
            live = moved          # a point that could not improve stays where it is
        return P, f, g

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

    def bisect(self, kinds, A, B, ref, tol, iters=60, crease_angle=None):
        """Zero crossings between bracket ends A, B (on the surface, opposite signs).

        Regula falsi with the Illinois modification on the segment A-B, every trial
        point projected onto the surface; creases (where the sign jumps rather than
        crosses zero) are bisected. Returns the crossing (the final bracket end on the
        first end's side, on the surface to rounding), its gradient, the final bracket
        ends and their normals, and whether each bracket held a sign change. With
        ``crease_angle``, a crease bracket whose end normals come within half of it is
        a smooth bend, not a crease: it stops at once, invalid (narrowing a smooth
        surface only brings the normals closer; a crease keeps them apart)."""
        A, fA, gA = self.project(A)
        B, fB, gB = self.project(B)
        sA = self.signs(kinds, A, gA, ref)
        sB = self.signs(kinds, B, gB, ref)
        valid = (sA > 0) != (sB > 0)
        A, B, gA, gB = A.copy(), B.copy(), gA.copy(), gB.copy()
        jump = kinds == CREASE
        last = np.zeros(len(A), np.int8)        # which end moved last (Illinois)
        width = np.linalg.norm(A - B, axis=1)
        stalls = np.zeros(len(A), np.int64)
        live = np.flatnonzero(valid)
        check = width.copy()                     # width at the last progress check
        for it in range(iters):
            if len(live) == 0:
                break
            w = np.linalg.norm(A[live] - B[live], axis=1)
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
            if crease_angle is not None:
                jl = np.flatnonzero(jump[live] & ~dead)
                if len(jl):
                    j = live[jl]
                    cos = np.einsum("ij,ij->i", self.normals(gA[j]), self.normals(gB[j]))
                    dead[jl[cos > np.cos(0.5 * crease_angle)]] = True
            valid[live[dead]] = False
            live, w = live[~dead], w[~dead]
            live = live[w > tol]
            if len(live) == 0:
                break
            a, b = sA[live], sB[live]
            u = np.where(jump[live], 0.5, a / np.where(a - b == 0, 1.0, a - b))
            u = np.clip(u, 0.02, 0.98)
            M, fM, gM = self.project(A[live] + u[:, None] * (B[live] - A[live]), steps=4)
            sM = self.signs(kinds[live], M, gM, ref[live])
            # a smooth crossing is found when its signed quantity vanishes (to 1e-11;
            # n.v is a cosine, mean curvature is scaled by the model's size)
            hit = ~jump[live] & (np.abs(sM) * np.where(kinds[live] == CURV, self.scale, 1.0) < 1e-11)
            if hit.any():
                ih = live[hit]
                A[ih], gA[ih], B[ih], gB[ih] = M[hit], gM[hit], M[hit], gM[hit]
                keep = ~hit
                live, M, gM, sM = live[keep], M[keep], gM[keep], sM[keep]
                if len(live) == 0:
                    break
            sideA = (sM > 0) == (sA[live] > 0)
            ia, ib = live[sideA], live[~sideA]
            A[ia], gA[ia], sA[ia] = M[sideA], gM[sideA], sM[sideA]
            B[ib], gB[ib], sB[ib] = M[~sideA], gM[~sideA], sM[~sideA]
            # Illinois: halve the stale end's value when the same end moves twice
            sB[ia[last[ia] == 1]] *= 0.5
            sA[ib[last[ib] == 2]] *= 0.5
            last[ia], last[ib] = 1, 2
        else:                                    # out of iterations: unconverged smooth ones are invalid
            if len(live):
                open_ = (np.linalg.norm(A[live] - B[live], axis=1) > tol) & ~jump[live]
                valid[live[open_]] = False
        return A, gA, A, B, self.normals(gA), self.normals(gB), valid
