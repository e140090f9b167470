"""Measures of a drawing's tone marks against the exact surface (pure numpy), shared by
bench/quality.py and the core tests. Independent of how the marks were placed: the
target comes from ray casting the exact field from the camera, the ink from
rasterising the plain strokes (both bench/inkview.py). Definitions: bench/README.md
(quality.py).

    out = tone_figures(target, ink, mask, res)          # tone_r, evenness, means
    out.update(dot_figures(cam, dots))                  # nn_cv, touching
"""
import math

import numpy as np

from blobtree_ink.model.curvature import curvature
from blobtree_ink.strokes import tone as TN

from inkview import MARCH, hidden, stroke_pixels

BLUR = 0.015            # the Gaussian's sigma, as a share of the image width
ANGLE = 20.0            # degrees: a hatching segment within this of its field runs along it
DISTINCT = 0.1          # principal directions are distinct where |k1 - k2| > DISTINCT max(|k1|, |k2|)
END_RADIUS = 15.0       # px at 1024: stroke ends counted about each end
NEIGHBOURS = 6          # a dot's local expected spacing: the mean distance to this many nearest dots
TONE_LAYERS = ("Hatching", "Chains", "Short Strokes", "Stipples")
OUTLINE_LAYERS = ("Silhouette", "Crease", "Curvature", "Suggestive", "Ridges")


def blur(img, mask, sigma):
    """Normalised Gaussian blur of ``img`` within ``mask`` (values outside do not leak in)."""
    r = int(math.ceil(3 * sigma))
    x = np.arange(-r, r + 1)
    g = np.exp(-0.5 * (x / sigma) ** 2)
    g /= g.sum()

    def sep(a):
        a = np.apply_along_axis(lambda v: np.convolve(v, g, "same"), 0, a)
        return np.apply_along_axis(lambda v: np.convolve(v, g, "same"), 1, a)
    m = mask.astype(float)
    return sep(np.where(mask, img, 0.0)) / np.maximum(sep(m), 1e-12)


# --- figures --------------------------------------------------------------------------

def tone_figures(target, ink, mask, res):
    """tone_r, evenness (mean CV over the deciles of the wanted tone) and the means."""
    sigma = BLUR * res
    T, K = blur(target, mask, sigma)[mask], blur(ink, mask, sigma)[mask]
    out = {"mean_tone": float(T.mean()) if len(T) else math.nan, "mean_ink": float(K.mean()) if len(K) else math.nan}
    out["tone_r"] = float(np.corrcoef(T, K)[0, 1]) if len(T) > 2 and T.std() > 0 and K.std() > 0 else math.nan
    wanted = T > 0.02 * TN.DARKEST
    cvs = []
    if wanted.sum() >= 100:
        edges = np.quantile(T[wanted], np.linspace(0, 1, 11))
        which = np.clip(np.searchsorted(edges, T[wanted], "right") - 1, 0, 9)
        for d in range(10):
            k = K[wanted][which == d]
            if len(k) >= 10 and k.mean() > 0:
                cvs.append(k.std() / k.mean())
            elif len(k) >= 10:
                cvs.append(math.inf)           # a tone that wants ink and gets none
    out["evenness"] = float(np.mean(cvs)) if cvs else math.nan
    return out


def nearest(XY, k):
    """Distances to the k nearest other points (n, k), in blocks."""
    XY = np.asarray(XY, float)
    out = np.full((len(XY), k), np.inf)
    if len(XY) < 2:
        return out
    sq = (XY ** 2).sum(1)
    for a in range(0, len(XY), 1024):
        d2 = sq[a:a + 1024, None] + sq[None, :] - 2 * XY[a:a + 1024] @ XY.T
        d2[np.arange(len(d2)), np.arange(a, a + len(d2))] = np.inf
        kk = min(k, len(XY) - 1)
        part = np.sqrt(np.maximum(np.partition(d2, kk - 1, axis=1)[:, :kk], 0.0))
        out[a:a + 1024, :kk] = np.sort(part, axis=1)
    return out


def dot_figures(cam, dots):
    """nn_cv: the coefficient of variation of each dot's nearest-neighbour distance over
    its local expected spacing (the mean distance to its NEIGHBOURS nearest); touching:
    the share of dots that touch or overlap another (at 1024 px)."""
    if len(dots) < NEIGHBOURS + 2:
        return {"dots": len(dots), "nn_cv": math.nan, "touching": math.nan}
    xy = np.concatenate([stroke_pixels(cam, s, 1024)[0] for s in dots])
    r = np.concatenate([stroke_pixels(cam, s, 1024)[1] for s in dots])
    d = nearest(xy, NEIGHBOURS)
    ratio = d[:, 0] / d.mean(axis=1)
    touch = np.zeros(len(xy), bool)
    sq = (xy ** 2).sum(1)
    for a in range(0, len(xy), 1024):
        d2 = sq[a:a + 1024, None] + sq[None, :] - 2 * xy[a:a + 1024] @ xy.T
        d2[np.arange(len(d2)), np.arange(a, a + len(d2))] = np.inf
        touch[a:a + 1024] = (np.sqrt(np.maximum(d2, 0)) < r[a:a + 1024, None] + r[None, :]).any(axis=1)
    return {"dots": len(dots), "nn_cv": float(ratio.std() / ratio.mean()), "touching": float(touch.mean())}


def field_directions(ev, P, field, eye, axis):
    """The directions a hatching layer's ``field`` follows at points P (two per point,
    for a field of principal directions: either counts), and where they are defined."""
    c = curvature(ev, P)
    N = c["normal"]
    k1, k2 = c["k1"], c["k2"]
    distinct = np.abs(k1 - k2) > DISTINCT * np.maximum(np.abs(k1), np.abs(k2))
    if field in ("dir1", "dir2"):
        return [c["dir1"], c["dir2"]], distinct
    if field == "diagonal":
        a = c["dir1"] + c["dir2"]
        b = c["dir1"] - c["dir2"]
        return [a / np.linalg.norm(a, axis=1, keepdims=True), b / np.linalg.norm(b, axis=1, keepdims=True)], distinct
    if field == "contour":
        d = np.cross(N, eye - P)
    elif field == "level":
        d = np.cross(N, np.broadcast_to(np.asarray(axis, float), N.shape))
    elif field == "axis":
        a = np.broadcast_to(np.asarray(axis, float), N.shape)
        d = a - np.einsum("ij,ij->i", a, N)[:, None] * N
    else:
        return None, np.zeros(len(P), bool)
    n = np.linalg.norm(d, axis=1, keepdims=True)
    return [d / np.maximum(n, 1e-300)], n[:, 0] > 1e-9


def hatch_figures(ev, cam, layers, eye):
    """along: the share of the hatching's length (at 1024 px) within ANGLE degrees of the
    field it follows, where that field is defined (``layers``: (strokes, field, axis)
    each); ends: the most stroke ends within END_RADIUS px of one stroke end."""
    total = along = 0.0
    ends = []
    for strokes, field, axis in layers:
        segs = [s for s in strokes if len(s.points) > 1]
        if not segs:
            continue
        for s in segs:
            xy, _ = cam.pixels(s.points, 1024)
            ends += [xy[0], xy[-1]]
        A = np.concatenate([s.points[:-1] for s in segs])
        B = np.concatenate([s.points[1:] for s in segs])
        M = 0.5 * (A + B)
        dirs, defined = field_directions(ev, M, field, np.asarray(eye, float), axis)
        if dirs is None:
            continue
        a, _ = cam.pixels(A, 1024)
        b, _ = cam.pixels(B, 1024)
        m, _ = cam.pixels(M, 1024)
        seg = b - a
        length = np.linalg.norm(seg, axis=1)
        best = np.zeros(len(M))
        for d in dirs:
            e = cam.pixels(M + 1e-4 * ev.scale * d, 1024)[0] - m
            cos = np.abs(np.einsum("ij,ij->i", seg, e)) / np.maximum(length * np.linalg.norm(e, axis=1), 1e-300)
            best = np.maximum(best, cos)
        ok = defined & (length > 0)
        total += length[ok].sum()
        along += length[ok & (best >= math.cos(math.radians(ANGLE)))].sum()
    most = 0
    if ends:
        E = np.array(ends)
        d = nearest(E, min(128, len(E) - 1)) if len(E) > 1 else np.zeros((1, 0))
        most = int(((d <= END_RADIUS).sum(axis=1) + 1).max())
    return {"along": along / total if total > 0 else math.nan, "ends": most}


def _segments_2d(strokes, cam):
    out = []
    for s in strokes:
        xy, r, _ = stroke_pixels(cam, s, 1024)
        if s.cyclic and len(xy) > 2:
            xy, r = np.vstack([xy, xy[:1]]), np.append(r, r[0])
        if len(xy) > 1:
            out.append(np.column_stack([xy[:-1], xy[1:], np.maximum(r[:-1], r[1:])]))
    return np.concatenate(out) if out else np.zeros((0, 5))


def crossing_figures(ev, cam, tone_strokes, outlines):
    """outside: tone marks with a point hidden from the eye (but where it goes behind
    the outline that hides it, within that outline's width) or off the surface;
    crossing: tone marks that cross a visible outline and go on beyond it by more than
    the outline's width (a dot: whose disc reaches that far past the line's middle)."""
    outside = 0
    P = [s.points for s in tone_strokes]
    L = _segments_2d(outlines, cam)
    width = 2 * L[:, 4]                     # each outline segment's width, px
    if P:
        allP = np.concatenate(P)
        f, g = ev.field_grad(allP)
        off = np.abs(f - ev.iso) / np.maximum(np.linalg.norm(g, axis=1), 1e-300) > 1e-3 * ev.scale
        hid = hidden(ev, cam, allP, slack=5 * MARCH * ev.scale)
        if hid.any() and len(L):            # a mark that ends where it goes behind: at the outline that hides it
            xy, _ = cam.pixels(allP[hid], 1024)
            k = np.flatnonzero(hid)
            for n, x in zip(k, xy):
                d = _point_segment(np.repeat(x[None], len(L), 0), L[:, 0:2], L[:, 2:4])
                hid[n] = not (d <= width).any()
        bad = off | hid
        sizes = np.array([len(p) for p in P])
        outside = int(np.add.reduceat(bad.astype(int), np.cumsum(sizes) - sizes).astype(bool).sum())
    crossing = 0
    if len(L) == 0:
        return {"outside": outside, "crossing": 0}
    C, D = L[:, 0:2], L[:, 2:4]
    mid = 0.5 * (C + D)
    reach = 0.5 * np.linalg.norm(D - C, axis=1).max()
    from blobtree_ink.blackboard.cells import pairs_within
    for s in tone_strokes:
        xy, r, _ = stroke_pixels(cam, s, 1024)
        if len(xy) == 1 or s.dots:
            i, j = pairs_within(np.c_[xy, np.zeros(len(xy))], np.c_[mid, np.zeros(len(mid))], reach + r.max() + 1)
            if len(j):
                d = _point_segment(xy[i], C[j], D[j])
                crossing += int((d + width[j] < r[i]).any())
            continue
        A, B = xy[:-1], xy[1:]
        arc = np.r_[0.0, np.cumsum(np.linalg.norm(B - A, axis=1))]
        sm = 0.5 * (A + B)
        half = 0.5 * np.linalg.norm(B - A, axis=1).max()
        i, j = pairs_within(np.c_[sm, np.zeros(len(sm))], np.c_[mid, np.zeros(len(mid))], reach + half + 1)
        if not len(i):
            continue
        t, ok = _intersect(A[i], B[i], C[j], D[j])
        if not ok.any():
            continue
        at = arc[i[ok]] + t[ok] * (arc[i[ok] + 1] - arc[i[ok]])
        beyond = np.minimum(at, arc[-1] - at)
        crossing += int((beyond > width[j[ok]]).any())
    return {"outside": outside, "crossing": crossing}


def _point_segment(X, A, B):
    AB = B - A
    t = np.clip(np.einsum("ij,ij->i", X - A, AB) / np.maximum(np.einsum("ij,ij->i", AB, AB), 1e-12), 0, 1)
    return np.linalg.norm(X - A - t[:, None] * AB, axis=1)


def _intersect(A, B, C, D):
    """Where segments AB cross segments CD: the parameter along AB, and whether they do."""
    r, s = B - A, D - C
    den = r[:, 0] * s[:, 1] - r[:, 1] * s[:, 0]
    q = C - A
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (q[:, 0] * s[:, 1] - q[:, 1] * s[:, 0]) / den
        u = (q[:, 0] * r[:, 1] - q[:, 1] * r[:, 0]) / den
    ok = (np.abs(den) > 1e-12) & (t >= 0) & (t <= 1) & (u >= 0) & (u <= 1)
    return np.where(ok, t, 0.0), ok
