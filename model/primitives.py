"""Skeletal primitives as batched geometry: packed parameters, bounds, distances.

Every primitive kind provides ``dist2(P, prm, idx)`` returning ``(d2, V)`` for the
points ``P`` (3,n) against primitives ``idx`` (n,) of a packed group, where ``d2`` is
the squared distance to the skeleton and ``V`` is half its gradient (so
``grad d2 = 2 V``). The kernel of the format, ``f = s * (1 - d2/R^2)^3``, is applied
in :func:`kernel`; one code path serves a single point (a batch of one), a group of
thousands of primitives, and the naive reference evaluation.
"""
import numpy as np

from . import nodes as N

KINDS = ("point", "segment", "circle", "disc", "box")


def _unit(v):
    v = np.asarray(v, float)
    return v / np.linalg.norm(v)


def pack(prims):
    """Pack primitives of one kind into a dict of (m, ...) float arrays."""
    kind = N.TYPE_NAME[type(prims[0])]
    R = np.array([p.radius for p in prims], float)
    S = np.array([p.strength for p in prims], float)
    prm = {"kind": kind, "R": R, "S": S, "R2": R * R, "invR2": 1.0 / (R * R)}
    if kind == "point":
        prm["C"] = np.array([p.center for p in prims], float)
    elif kind == "segment":
        A = np.array([p.a for p in prims], float)
        B = np.array([p.b for p in prims], float)
        AB = B - A
        L2 = np.einsum("ij,ij->i", AB, AB)
        prm.update(A=A, B=B, AB=AB, invL2=np.where(L2 > 0, 1.0 / np.where(L2 > 0, L2, 1), 0.0))
    elif kind in ("circle", "disc"):
        prm["C"] = np.array([p.center for p in prims], float)
        prm["Nrm"] = np.array([_unit(p.normal) for p in prims], float)
        prm["RC"] = np.array([p.circle_radius if kind == "circle" else p.disc_radius
                              for p in prims], float)
    elif kind == "box":
        prm["C"] = np.array([p.center for p in prims], float)
        prm["H"] = np.array([p.half_size for p in prims], float)
    return soa(prm)


def skeleton_bounds(prm):
    """(m,3) lower and upper corners of each skeleton."""
    kind = prm["kind"]
    if kind == "point":
        return prm["C"], prm["C"]
    if kind == "segment":
        return np.minimum(prm["A"], prm["B"]), np.maximum(prm["A"], prm["B"])
    if kind in ("circle", "disc"):
        ext = prm["RC"][:, None] * np.sqrt(np.maximum(0.0, 1.0 - prm["Nrm"] ** 2))
        return prm["C"] - ext, prm["C"] + ext
    if kind == "box":
        return prm["C"] - prm["H"], prm["C"] + prm["H"]
    raise AssertionError(kind)


def support_bounds(prm):
    lo, hi = skeleton_bounds(prm)
    R = prm["R"][:, None]
    return lo - R, hi + R


def soa(prm):
    """Column (3, m) copies of the packed vectors, for the (3, n) evaluation layout."""
    for key in ("C", "A", "AB", "Nrm", "H"):
        if key in prm:
            prm[key + "t"] = np.ascontiguousarray(prm[key].T)
    return prm


def dist2(P, prm, idx=None):
    """Squared distance of each point to its primitive's skeleton, and half its gradient.

    ``P`` is (3, n) (one row per coordinate); ``idx`` selects, per point, the primitive
    of the group (None: the group has exactly one primitive). Returns d2 (n,) and
    V (3, n) with grad d2 = 2 V.
    """
    kind = prm["kind"]
    if idx is None:
        def take(key):
            a = prm[key]
            return a[:, 0:1] if a.ndim == 2 else a[0]
    else:
        def take(key):
            a = prm[key]
            return a.take(idx, axis=a.ndim - 1)
    if kind == "point":
        V = P - take("Ct")
        return V[0] * V[0] + V[1] * V[1] + V[2] * V[2], V
    if kind == "segment":
        D = P - take("At")
        AB = take("ABt")
        t = (D[0] * AB[0] + D[1] * AB[1] + D[2] * AB[2]) * take("invL2")
        np.clip(t, 0.0, 1.0, out=t)
        V = D - t * AB
        return V[0] * V[0] + V[1] * V[1] + V[2] * V[2], V
    if kind in ("circle", "disc"):
        D = P - take("Ct")
        n = take("Nrmt")
        h = D[0] * n[0] + D[1] * n[1] + D[2] * n[2]
        W = D - h * n
        rho = np.sqrt(W[0] * W[0] + W[1] * W[1] + W[2] * W[2])
        rc = take("RC")
        e = rho - rc
        if kind == "disc":
            np.maximum(e, 0.0, out=e)
        with np.errstate(divide="ignore", invalid="ignore"):
            scale = np.where(rho > 0, e / rho, 0.0)
        V = h * n + scale * W
        return h * h + e * e, V
    if kind == "box":
        Q = P - take("Ct")
        H = take("Ht")
        V = Q - np.clip(Q, -H, H)
        return V[0] * V[0] + V[1] * V[1] + V[2] * V[2], V
    raise AssertionError(kind)


def kernel(d2, V, prm, idx, need_grad):
    """Field s*(1-t)^3 (t = d2/R^2 < 1, else 0) and its gradient (3, n) for each pair."""
    if idx is None:
        invR2 = prm["invR2"][0]
        S = prm["S"][0]
    else:
        invR2 = prm["invR2"][idx]
        S = prm["S"][idx]
    u = 1.0 - d2 * invR2
    np.maximum(u, 0.0, out=u)
    u2 = u * u
    f = S * u2 * u
    if not need_grad:
        return f, None
    # d/dp [s (1 - d2/R^2)^3] = -3 s (1-t)^2 / R^2 * 2 V
    return f, ((-6.0 * S * invR2) * u2) * V


def fold_similarity(prim, M, t):
    """The primitive mapped by p -> M p + t where M = s*Q (Q orthogonal), or None when
    its skeleton cannot be expressed in the new frame (a rotated box)."""
    s = abs(np.linalg.det(M)) ** (1.0 / 3.0)
    kind = N.TYPE_NAME[type(prim)]

    def mp(v):
        return tuple(float(x) for x in (M @ np.asarray(v, float) + t))

    def mv(v):
        return tuple(float(x) for x in (M @ np.asarray(v, float)))
    common = dict(radius=prim.radius * s, strength=prim.strength, name=prim.name)
    if kind == "point":
        return N.Point(center=mp(prim.center), **common)
    if kind == "segment":
        return N.Segment(a=mp(prim.a), b=mp(prim.b), **common)
    if kind == "circle":
        return N.Circle(center=mp(prim.center), normal=mv(prim.normal),
                        circle_radius=prim.circle_radius * s, **common)
    if kind == "disc":
        return N.Disc(center=mp(prim.center), normal=mv(prim.normal),
                      disc_radius=prim.disc_radius * s, **common)
    if kind == "box":
        Q = M / s
        if not np.allclose(np.abs(Q), np.eye(3), atol=1e-12):
            return None
        return N.Box(center=mp(prim.center), half_size=tuple(float(x) * s for x in prim.half_size),
                     **common)
    raise AssertionError(kind)
