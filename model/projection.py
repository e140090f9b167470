"""Damped Newton projection onto the iso-surface f = iso: the one implementation the
polygoniser (its vertices) and the agents (their surface points) share.

Each step moves a point along the gradient by -(f - iso) g / |g|^2, clamped to
``max_step``. A step after which |f - iso| is larger is not taken; that point's next step
is halved instead (down to 1/32 of a full step, after which it stays where it is), and a
step that was taken lets the next one grow back (times 2, up to a full step). Only the
points not yet on the surface are evaluated, and every step is a single batched field
evaluation: ``steps`` bounds the number of evaluations, not only of moves (a rejected
step costs no evaluation of its own: field calls on small batches cost about the same
as on large ones).
"""
import numpy as np

from .tolerances import CONVERGED, field_tol

MIN_DAMP = 1.0 / 32.0


def newton(ev, P, f, g, steps, max_step=None):
    """Move P (m,3) in place onto f = iso, updating f (m,) and g (m,3) with it.

    Points where the gradient vanishes (a flat field) cannot move and are left as they
    are. Returns the number of field evaluations made."""
    iso = ev.iso
    tol = field_tol(iso, CONVERGED)
    live = np.arange(len(P))
    damp = np.ones(len(P))
    calls = 0
    for _ in range(steps):
        fl, gl = f[live], g[live]
        gg = np.einsum("ij,ij->i", gl, gl)
        ok = (gg > 1e-300) & (np.abs(fl - iso) > tol) & (damp[live] >= MIN_DAMP)
        live, fl, gl, gg = live[ok], fl[ok], gl[ok], gg[ok]
        if len(live) == 0:
            break
        d = -((fl - iso) / gg)[:, None] * gl
        if max_step is not None:
            L = np.linalg.norm(d, axis=1)
            d *= np.where(L > max_step, max_step / np.maximum(L, 1e-300), 1.0)[:, None]
        d *= damp[live][:, None]
        Q = P[live] + d
        fq, gq = ev.field_grad(Q)
        calls += 1
        better = np.abs(fq - iso) <= np.abs(fl - iso)
        moved = live[better]
        P[moved], f[moved], g[moved] = Q[better], fq[better], gq[better]
        damp[moved] = np.minimum(1.0, 2.0 * damp[moved])
        damp[live[~better]] *= 0.5
    return calls


def project(ev, P, steps, max_step=None):
    """A copy of P (m,3) moved onto f = iso by :func:`newton`; returns it with f and g
    there."""
    P = np.array(P, float).reshape(-1, 3)
    f, g = ev.field_grad(P)
    newton(ev, P, f, g, steps, max_step)
    return P, f, g
