"""Warps and transforms: q = W^-1(p) on (3, n) batches (one row per coordinate) with the
Jacobian dq/dp ((3, 3) when constant, else (3, 3, n)), the forward map p = W(q) (where a
point of the child lands: marks placed on a primitive), and the forward image of a
bounding box (where the warped child's support can land)."""
import math

import numpy as np

INF = np.inf


def euler_xyz(rot):
    """Blender's XYZ Euler rotation matrix (X applied first): Rz @ Ry @ Rx."""
    x, y, z = rot
    cx, sx, cy, sy, cz, sz = math.cos(x), math.sin(x), math.cos(y), math.sin(y), math.cos(z), math.sin(z)
    Rx = np.array([[1, 0, 0], [0, cx, -sx], [0, sx, cx]])
    Ry = np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
    Rz = np.array([[cz, -sz, 0], [sz, cz, 0], [0, 0, 1]])
    return Rz @ Ry @ Rx


def transform_matrix(translate, rotate, scale):
    """W = T R S as a linear part L and translation t: W(q) = L q + t."""
    L = euler_xyz(rotate) @ np.diag(np.asarray(scale, float))
    return L, np.asarray(translate, float)


def affine_inverse(L, t):
    """(A, b) with q = A p + b the inverse of p = L q + t."""
    A = np.linalg.inv(L)
    return A, -A @ t


def box_corners(lo, hi):
    return np.array([[lo[0] if i & 1 == 0 else hi[0],
                      lo[1] if i & 2 == 0 else hi[1],
                      lo[2] if i & 4 == 0 else hi[2]] for i in range(8)], float)


def unbounded(lo, hi):
    return not (np.all(np.isfinite(lo)) and np.all(np.isfinite(hi)))


# --- affine (the transform node, and folded similarity transforms) ------------------

def affine_map(P, A, b, need_jac):
    Q = A @ P + b[:, None]
    return Q, (A if need_jac else None)


def affine_bounds(lo, hi, L, t):
    if unbounded(lo, hi):
        return np.full(3, -INF), np.full(3, INF)
    c = box_corners(lo, hi) @ L.T + t
    return c.min(0), c.max(0)


# --- twist --------------------------------------------------------------------------

def twist_map(P, rate, need_jac):
    x, y, z = P
    a = -rate * z
    c, s = np.cos(a), np.sin(a)
    Q = np.empty_like(P)
    Q[0] = c * x - s * y
    Q[1] = s * x + c * y
    Q[2] = z
    if not need_jac:
        return Q, None
    J = np.zeros((3, 3, P.shape[1]))
    J[0, 0] = c
    J[0, 1] = -s
    J[0, 2] = rate * Q[1]
    J[1, 0] = s
    J[1, 1] = c
    J[1, 2] = -rate * Q[0]
    J[2, 2] = 1.0
    return Q, J


def twist_forward(Q, rate):
    """p = W(q): the inverse of :func:`twist_map` (a rotation by +rate*z about z)."""
    x, y, z = Q
    a = rate * z
    c, s = np.cos(a), np.sin(a)
    return np.stack([c * x - s * y, s * x + c * y, z])


def twist_bounds(lo, hi, rate):
    if unbounded(lo, hi):
        return np.full(3, -INF), np.full(3, INF)
    if rate == 0:
        return lo.copy(), hi.copy()
    r = math.sqrt(max(lo[0] ** 2, hi[0] ** 2) + max(lo[1] ** 2, hi[1] ** 2))
    return np.array([-r, -r, lo[2]]), np.array([r, r, hi[2]])


# --- taper --------------------------------------------------------------------------

TAPER_MIN = 0.05


def taper_map(P, rate, need_jac):
    raw = 1.0 + rate * P[2]
    s = np.maximum(raw, TAPER_MIN)
    inv = 1.0 / s
    Q = P.copy()
    Q[0] *= inv
    Q[1] *= inv
    if not need_jac:
        return Q, None
    J = np.zeros((3, 3, P.shape[1]))
    J[0, 0] = inv
    J[1, 1] = inv
    ds = np.where(raw > TAPER_MIN, rate, 0.0)   # the clamp has zero slope
    J[0, 2] = -P[0] * ds * inv * inv
    J[1, 2] = -P[1] * ds * inv * inv
    J[2, 2] = 1.0
    return Q, J


def taper_forward(Q, rate):
    """p = W(q): x and y scaled by max(1 + rate*z, TAPER_MIN) (z is kept, so the
    scale is known from q)."""
    s = np.maximum(1.0 + rate * Q[2], TAPER_MIN)
    return np.stack([Q[0] * s, Q[1] * s, Q[2]])


def taper_bounds(lo, hi, rate):
    if unbounded(lo, hi):
        return np.full(3, -INF), np.full(3, INF)
    s1 = max(1.0 + rate * lo[2], TAPER_MIN)
    s2 = max(1.0 + rate * hi[2], TAPER_MIN)
    out_lo, out_hi = lo.copy(), hi.copy()
    for i in (0, 1):
        prods = [lo[i] * s1, lo[i] * s2, hi[i] * s1, hi[i] * s2]
        out_lo[i], out_hi[i] = min(prods), max(prods)
    return out_lo, out_hi


# --- bend ---------------------------------------------------------------------------

def bend_map(P, rate, need_jac):
    if rate == 0:
        return P, (np.eye(3) if need_jac else None)
    r = 1.0 / rate
    sg = 1.0 if rate > 0 else -1.0
    x, y, z = P
    w = r - z
    theta = np.arctan2(sg * x, sg * w)
    rho2 = x * x + w * w
    rho = np.sqrt(rho2)
    Q = np.empty_like(P)
    Q[0] = theta * r
    Q[1] = y
    Q[2] = r - sg * rho
    if not need_jac:
        return Q, None
    with np.errstate(divide="ignore", invalid="ignore"):
        inv2 = np.where(rho2 > 0, 1.0 / rho2, 0.0)
    inv1 = np.sqrt(inv2)
    J = np.zeros((3, 3, P.shape[1]))
    J[0, 0] = r * w * inv2
    J[0, 2] = r * x * inv2
    J[1, 1] = 1.0
    J[2, 0] = -sg * x * inv1
    J[2, 2] = sg * w * inv1
    return Q, J


def bend_forward(Q, rate):
    """p = W(q): the inverse of :func:`bend_map` (x along the arc of radius 1/rate)."""
    if rate == 0:
        return np.array(Q, float)
    r = 1.0 / rate
    sg = 1.0 if rate > 0 else -1.0
    theta = Q[0] / r
    rho = sg * (r - Q[2])
    return np.stack([sg * rho * np.sin(theta), Q[1], r - sg * rho * np.cos(theta)])


def bend_bounds(lo, hi, rate):
    """Image of the child's box under the forward bend p = W(q)."""
    if unbounded(lo, hi):
        return np.full(3, -INF), np.full(3, INF)
    if rate == 0 or np.any(lo > hi):            # no bend, or an empty support (it stays empty)
        return lo.copy(), hi.copy()
    r = 1.0 / rate
    sg = 1.0 if rate > 0 else -1.0
    # rho = sg*(r - q2) must be >= 0; theta = q0 / r lies in [-pi, pi]
    rr = sorted([sg * (r - lo[2]), sg * (r - hi[2])])
    rho_lo, rho_hi = max(rr[0], 0.0), max(rr[1], 0.0)
    th = sorted([lo[0] / r, hi[0] / r])
    th_lo, th_hi = max(th[0], -math.pi), min(th[1], math.pi)
    if th_lo > th_hi:   # the child's support lies where the bend never reaches
        return np.full(3, INF), np.full(3, -INF)
    angles = [th_lo, th_hi] + [k * math.pi / 2 for k in range(-2, 3) if th_lo < k * math.pi / 2 < th_hi]
    sins = [math.sin(a) for a in angles]
    coss = [math.cos(a) for a in angles]
    xs = [sg * rho * s for rho in (rho_lo, rho_hi) for s in sins]
    zs = [r - sg * rho * c for rho in (rho_lo, rho_hi) for c in coss]
    return (np.array([min(xs), lo[1], min(zs)]), np.array([max(xs), hi[1], max(zs)]))
