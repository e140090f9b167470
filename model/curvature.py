"""Surface differential geometry of the iso-surface from the field.

The gradient is analytic (see :mod:`.evaluate`); the Hessian is the central
difference of that analytic gradient with step ``h = HESSIAN_STEP * scale`` (scale:
the diagonal of the model's bounds), six extra gradient evaluations per sample. The
shape operator is the tangential part of the Hessian over |grad f|, with the outward
normal n = -grad f / |grad f| (fields fall outward), so a convex surface has positive
curvature: a sphere of radius r has k1 = k2 = 1/r, mean 1/r, Gaussian 1/r^2.
"""
import numpy as np

from .evaluate import as_points
from .vectors import cross

HESSIAN_STEP = 1e-5


def hessian(ev, P, h=None):
    return field_grad_hessian(ev, P, h, centre=False)[2]


def field_grad_hessian(ev, P, h=None, centre=True):
    """Field, gradient and Hessian at P in one batched evaluation (the points and their
    six offsets); with ``centre`` False only the offsets are evaluated (f, g None)."""
    P = as_points(P)
    h = HESSIAN_STEP * ev.scale if h is None else h
    n = len(P)
    offs = np.concatenate([np.eye(3) * h, -np.eye(3) * h] + ([np.zeros((1, 3))] if centre else []))
    batch = (P[None, :, :] + offs[:, None, :]).reshape(-1, 3)
    f, g = ev.field_grad(batch)
    g = g.reshape(len(offs), n, 3)
    H = (g[:3] - g[3:6]).transpose(1, 0, 2) / (2 * h)    # H[n, i, j] = d g_j / d x_i
    H = 0.5 * (H + H.transpose(0, 2, 1))
    if not centre:
        return None, None, H
    return f[6 * n:], g[6], H


def field_grad_along(ev, P, dirs, h=None):
    """Field, gradient and the Hessian times each of ``dirs`` ((k, n, 3)) at P: forward
    differences of the analytic gradient along each direction, 1 + k points per point
    in one batch. A Newton step's Jacobian needs only H w, not all of H (whose forward
    differences take four points per point): the residuals stay exact, the Jacobian's
    error is of the order of h |w|. Returns f (n,), g (n, 3) and Hd (k, n, 3).
    (:func:`along_points` and :func:`along_values` are its two halves, for a solver
    that evaluates the batch itself.)"""
    B, L, h = along_points(ev, P, dirs, h)
    f, g = ev.field_grad(B)
    return along_values(f, g, L, h)


def along_points(ev, P, dirs, h=None):
    """The batch :func:`field_grad_along` evaluates: the points, then each point a
    step h along each direction; with the directions' lengths (k, n) and h."""
    P = as_points(P)
    h = HESSIAN_STEP * ev.scale if h is None else h
    D = np.asarray(dirs, float).reshape(-1, len(P), 3)
    L = np.linalg.norm(D, axis=2)                           # (k, n)
    U = D / np.maximum(L, 1e-300)[:, :, None]               # a zero direction stays zero
    return np.concatenate([P[None], P[None] + h * U]).reshape(-1, 3), L, h


def along_values(f, g, L, h):
    """f, g and Hd from the field and gradient on :func:`along_points`' batch."""
    k, n = L.shape
    g = g.reshape(k + 1, n, 3)
    return f[:n], g[0], (g[1:] - g[:1]) * (L / h)[:, :, None]


def curvature(ev, P, grad=None):
    """Dict of per-point arrays: normal, k1 >= k2, mean, gauss, dir1, dir2 (unit).
    The shape operator in a tangent basis (e1, e2) is a symmetric 2x2 matrix
    [[a, b], [b, c]]; its eigenvalues and eigenvectors are taken in closed form."""
    P = as_points(P)
    if grad is None:
        _, grad = ev.field_grad(P)
    H = hessian(ev, P)
    gn = np.linalg.norm(grad, axis=1)
    safe = np.where(gn > 0, gn, 1.0)
    nrm = -grad / safe[:, None]
    e1, e2 = tangent_basis(nrm)
    He1, He2 = np.einsum("nij,nj->ni", H, e1), np.einsum("nij,nj->ni", H, e2)
    a = -np.einsum("ni,ni->n", e1, He1) / safe
    b = -0.5 * (np.einsum("ni,ni->n", e2, He1) + np.einsum("ni,ni->n", e1, He2)) / safe
    c = -np.einsum("ni,ni->n", e2, He2) / safe
    half = 0.5 * (a - c)
    r = np.hypot(half, b)
    k1, k2 = 0.5 * (a + c) + r, 0.5 * (a + c) - r
    # k1's eigenvector, written the way that does not cancel: (r + half, b) or (b, r - half)
    big = half >= 0
    x = np.where(big, r + half, b)
    y = np.where(big, b, r - half)
    d1 = x[:, None] * e1 + y[:, None] * e2
    length = np.linalg.norm(d1, axis=1)
    umbilic = ~(length > 0)                               # every direction is principal: e1
    d1 = np.where(umbilic[:, None], e1, d1 / np.where(umbilic, 1.0, length)[:, None])
    d2 = cross(nrm, d1)
    bad = gn == 0
    for v in (k1, k2):
        v[bad] = np.nan
    return {"normal": nrm, "k1": k1, "k2": k2, "mean": 0.5 * (k1 + k2), "gauss": k1 * k2,
            "dir1": d1, "dir2": d2, "grad_norm": gn}


def tangent_basis(n):
    """Unit vectors e1, e2 with (e1, e2, n) right-handed and orthonormal, for unit
    normals n (n, 3); e1 is across the axis least aligned with n (a zero normal
    gets the x and y axes)."""
    axis = np.zeros_like(n)
    axis[np.arange(len(n)), np.argmin(np.abs(n), axis=1)] = 1.0
    e1 = cross(axis, n)
    length = np.linalg.norm(e1, axis=1)
    zero = ~(length > 0)
    e1 = np.where(zero[:, None], [1.0, 0.0, 0.0], e1 / np.where(zero, 1.0, length)[:, None])
    e2 = np.where(zero[:, None], [0.0, 1.0, 0.0], cross(n, e1))
    return e1, e2


def radial(c, towards_eye):
    """The radial curvature (DeCarlo et al. 2003) of points with curvature ``c`` (a
    :func:`curvature` dict) seen along ``towards_eye`` (unit, per point): the normal
    curvature in the direction w, the view direction projected onto the tangent plane,
    k1 cos^2 + k2 sin^2 of w's angle to dir1; with |w| (0 where the surface faces the
    eye head on, where it has no direction: NaN there)."""
    a = np.einsum("ij,ij->i", towards_eye, c["dir1"])
    b = np.einsum("ij,ij->i", towards_eye, c["dir2"])
    ww = a * a + b * b
    with np.errstate(invalid="ignore", divide="ignore"):
        kr = np.where(ww > 0, (c["k1"] * a * a + c["k2"] * b * b) / ww, np.nan)
    return kr, np.sqrt(ww)


def view_dependent(c, towards_eye):
    """The principal view-dependent curvature (Judd et al. 2007, apparent ridges) of
    points with curvature ``c`` (a :func:`curvature` dict) seen along ``towards_eye``
    (unit, per point): how fast the normal turns per unit of distance on the image
    plane, at most (the largest singular value of Q = S J^-1, J the projection of the
    tangent plane onto the plane across the view), signed as the surface's normal
    curvature along the direction it is taken in; and that direction on the surface,
    J^-1 t1 for the unit image direction t1 (unnormalised: its length is the surface
    distance per unit of image distance)."""
    n, d1, d2 = c["normal"], c["dir1"], c["dir2"]
    s1 = cross(towards_eye, n)
    head_on = np.linalg.norm(s1, axis=1) < 1e-9            # any image direction will do
    s1[head_on] = cross(towards_eye[head_on], np.where(np.abs(towards_eye[head_on, :1]) < 0.9,
                                                          [[1.0, 0, 0]], [[0, 1.0, 0]]))
    s1 /= np.linalg.norm(s1, axis=1, keepdims=True)
    s2 = cross(towards_eye, s1)
    J = np.stack([np.stack([np.einsum("ij,ij->i", d, s) for d in (d1, d2)], 1) for s in (s1, s2)], 1)
    det = J[:, 0, 0] * J[:, 1, 1] - J[:, 0, 1] * J[:, 1, 0]
    ok = np.isfinite(det) & (np.abs(det) > 1e-12) & np.isfinite(c["k1"]) & np.isfinite(c["k2"])
    S = np.zeros((len(n), 2, 2))            # none where there is no curvature (a flat field)
    S[ok, 0, 0], S[ok, 1, 1] = c["k1"][ok], c["k2"][ok]
    Ji = np.zeros_like(J)
    Ji[ok] = np.linalg.inv(J[ok])
    _, sig, Vt = np.linalg.svd(S @ Ji)
    ab = np.einsum("nij,nj->ni", Ji, Vt[:, 0, :])           # tangent coordinates along d1, d2
    sign = np.where(c["k1"] * ab[:, 0] ** 2 + c["k2"] * ab[:, 1] ** 2 < 0, -1.0, 1.0)
    q = np.where(ok, sign * sig[:, 0], np.nan)
    return q, ab[:, :1] * d1 + ab[:, 1:] * d2
