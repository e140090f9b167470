"""Measures of a drawing's tone marks against the exact surface (pure numpy), shared by
bench/quality.py and the core tests. Independent of how the marks were placed: the
target comes from ray casting the exact field from the camera, the ink from
rasterising the plain strokes. Definitions: bench/README.md (quality.py).

    cam = Camera.framing(eye, centre, points, size=1024)
    lit = cast_light(ev, cam, light, res=256)           # Lambert with cast shadows, NaN off the model
    m = measure(ev, cam, lit, strokes, style, ...)      # a dict of figures
"""
import math
import struct
import zlib

import numpy as np

from blobtree_ink.blackboard.polygonise import surface_box
from blobtree_ink.model.curvature import curvature
from blobtree_ink.pipeline.framing import MARGIN, crop
from blobtree_ink.strokes import tone as TN

BLUR = 0.015            # the Gaussian's sigma, as a share of the image width
ANGLE = 20.0            # degrees: a hatching segment within this of its field runs along it
DISTINCT = 0.1          # principal directions are distinct where |k1 - k2| > DISTINCT max(|k1|, |k2|)
END_RADIUS = 15.0       # px at 1024: stroke ends counted about each end
NEIGHBOURS = 6          # a dot's local expected spacing: the mean distance to this many nearest dots
MARCH = 0.002           # ray-march step, a share of the model's support diagonal
TONE_LAYERS = ("Hatching", "Chains", "Short Strokes", "Stipples")
OUTLINE_LAYERS = ("Silhouette", "Crease", "Curvature", "Suggestive", "Ridges")


class Camera:
    """A perspective camera at ``eye`` looking at ``centre`` (the world's z up), its
    square frame cut about some points as the command line cuts its picture."""

    def __init__(self, eye, centre, tan_half, shift, size):
        self.eye = np.asarray(eye, float)
        back = self.eye - np.asarray(centre, float)
        back /= np.linalg.norm(back)
        up = np.array([0.0, 0.0, 1.0]) if abs(back[2]) < 0.99 else np.array([0.0, 1.0, 0.0])
        right = np.cross(-back, up)
        right /= np.linalg.norm(right)
        self.axes = np.stack([right, np.cross(back, right), back], axis=1)
        self.tan_half, self.shift, self.size = float(tan_half), np.asarray(shift, float), int(size)

    @classmethod
    def framing(cls, eye, centre, points, size=1024):
        c = cls(eye, centre, 1.0, (0.0, 0.0), size)
        tan_half, sx, sy = crop(c.axes, c.eye, points, 1.0, MARGIN)
        return cls(eye, centre, tan_half, (sx, sy), size)

    def pixels(self, P, size=None):
        """Points (n, 3) as (x, y) pixels (y down) of a ``size`` wide picture, and their depths."""
        size = self.size if size is None else size
        rel = (np.asarray(P, float).reshape(-1, 3) - self.eye) @ self.axes
        depth = -rel[:, 2]
        uv = rel[:, :2] / depth[:, None] / (2 * self.tan_half) - self.shift
        return np.stack([(uv[:, 0] + 0.5) * size, (0.5 - uv[:, 1]) * size], axis=1), depth

    def px_per_unit(self, depth, size=None):
        """Pixels per model unit across the view at these depths."""
        return (self.size if size is None else size) / (2 * self.tan_half * np.asarray(depth, float))

    def rays(self, res):
        """Unit directions through the centres of a ``res`` x ``res`` picture's pixels (rows top down)."""
        c = (np.arange(res) + 0.5) / res
        u = (c - 0.5 + self.shift[0]) * 2 * self.tan_half
        v = (0.5 - c + self.shift[1]) * 2 * self.tan_half
        U, V = np.meshgrid(u, v)
        D = U.reshape(-1, 1) * self.axes[:, 0] + V.reshape(-1, 1) * self.axes[:, 1] - self.axes[:, 2]
        return D / np.linalg.norm(D, axis=1, keepdims=True)


# --- the exact surface, ray cast -------------------------------------------------------

def _box(ev):
    box = surface_box(ev)
    return box if box is not None else ev.bounds


def _clip(O, D, lo, hi):
    with np.errstate(divide="ignore", invalid="ignore"):
        a, b = (lo - O) / D, (hi - O) / D
    t0 = np.nanmax(np.where(np.isnan(np.minimum(a, b)), -np.inf, np.minimum(a, b)), axis=1)
    t1 = np.nanmin(np.where(np.isnan(np.maximum(a, b)), np.inf, np.maximum(a, b)), axis=1)
    return np.maximum(t0, 0.0), t1


def march(ev, O, D, step, until=None, batch=8):
    """The first parameter t of each ray O + t D (D unit) where the field reaches iso,
    sampled every ``step`` inside the model's box and up to ``until`` (inf: none), then
    bisected to the crossing; inf where none is."""
    O = np.broadcast_to(np.asarray(O, float), D.shape)
    t0, t1 = _clip(O, D, *_box(ev))
    if until is not None:
        t1 = np.minimum(t1, until)
    out = np.full(len(D), np.inf)
    live = np.flatnonzero(t1 > t0)
    k = 0
    while len(live):
        t = t0[live, None] + (k + np.arange(batch))[None, :] * step
        f = ev.field((O[live, None, :] + t[:, :, None] * D[live, None, :]).reshape(-1, 3)).reshape(t.shape)
        hit = (f >= ev.iso) & (t <= t1[live, None])
        got = hit.any(axis=1)
        rows = np.flatnonzero(got)
        first = hit[rows].argmax(axis=1)
        b = t[rows, first]
        a = np.where(first > 0, t[rows, np.maximum(first - 1, 0)], np.maximum(b - step, t0[live[rows]]))
        out[live[rows]] = _bisect(ev, O[live[rows]], D[live[rows]], a, b)
        live = live[~got & (t[:, -1] < t1[live])]
        k += batch
    return out


def _bisect(ev, O, D, a, b, halvings=40):
    for _ in range(halvings):
        m = 0.5 * (a + b)
        inside = ev.field(O + m[:, None] * D) >= ev.iso
        b = np.where(inside, m, b)
        a = np.where(inside, a, m)
    return b


def cast_light(ev, cam, light, res=256):
    """Per pixel of a ``res`` square picture: the Lambert light of the first surface its
    ray meets, 0 where the model casts a shadow on it, NaN where the ray meets no
    surface; also the hit points (NaN off the model)."""
    step = MARCH * ev.scale
    D = cam.rays(res)
    t = march(ev, cam.eye, D, step)
    hit = np.isfinite(t)
    P = np.full(D.shape, np.nan)
    P[hit] = cam.eye + t[hit, None] * D[hit]
    lit = np.full(len(D), np.nan)
    if hit.any():
        _, g = ev.field_grad(P[hit])
        N = -g / np.maximum(np.linalg.norm(g, axis=1, keepdims=True), 1e-300)
        lam = TN.lambert(N, light)
        L = np.asarray(light, float) / np.linalg.norm(light)
        facing = lam > 0
        start = P[hit][facing] + 2 * step * N[facing] + step * L
        shadow = np.isfinite(march(ev, start, np.broadcast_to(L, start.shape).copy(), step))
        lam[np.flatnonzero(facing)[shadow]] = 0.0
        lit[hit] = lam
    return lit.reshape(res, res), P.reshape(res, res, 3)


def hidden(ev, cam, P, slack):
    """Which points of the model a ray from the eye meets the surface before (by more
    than ``slack``): hidden ones."""
    P = np.asarray(P, float).reshape(-1, 3)
    if len(P) == 0:
        return np.zeros(0, bool)
    V = P - cam.eye
    d = np.linalg.norm(V, axis=1)
    t = march(ev, cam.eye, V / d[:, None], MARCH * ev.scale, until=d - slack)
    return t < d - slack


# --- the ink, rasterised ----------------------------------------------------------------

def stroke_pixels(cam, s, size):
    xy, depth = cam.pixels(s.points, size)
    return xy, np.asarray(s.radius, float) * cam.px_per_unit(depth, size), np.asarray(s.opacity, float)


def rasterise(cam, strokes, size):
    """The ink's coverage (0..1) of a ``size`` square picture: each stroke a chain of
    capsules (a dot a disc) of its radii and opacities, anti-aliased over a pixel, a
    stroke's own overlaps counted once, strokes over each other as layers of ink."""
    segs = []
    for k, s in enumerate(strokes):
        xy, r, o = stroke_pixels(cam, s, size)
        if len(xy) == 1 or s.dots:
            segs.append(np.column_stack([xy, xy, r, r, o, o, np.full(len(xy), k)]))
        else:
            if s.cyclic:
                xy, r, o = np.vstack([xy, xy[:1]]), np.append(r, r[0]), np.append(o, o[0])
            segs.append(np.column_stack([xy[:-1], xy[1:], r[:-1], r[1:], o[:-1], o[1:], np.full(len(xy) - 1, k)]))
    ink = np.zeros(size * size)
    if not segs:
        return ink.reshape(size, size)
    S = np.concatenate(segs)
    for part in np.array_split(S, max(1, len(S) // 20000 + 1)):
        _splat(part, size, ink)
    return 1.0 - np.exp(ink).reshape(size, size)


def _splat(S, size, log_clear):
    A, B, r0, r1, o0, o1, who = S[:, 0:2], S[:, 2:4], S[:, 4], S[:, 5], S[:, 6], S[:, 7], S[:, 8].astype(np.int64)
    R = np.maximum(r0, r1) + 1.0
    lo = np.floor(np.minimum(A, B) - R[:, None]).astype(np.int64)
    hi = np.ceil(np.maximum(A, B) + R[:, None]).astype(np.int64)
    lo, hi = np.clip(lo, 0, size), np.clip(hi, 0, size)
    w, h = np.maximum(hi[:, 0] - lo[:, 0], 0), np.maximum(hi[:, 1] - lo[:, 1], 0)
    n = w * h
    seg = np.repeat(np.arange(len(S)), n)
    if len(seg) == 0:
        return
    local = np.arange(len(seg)) - np.repeat(np.cumsum(n) - n, n)
    x = lo[seg, 0] + local % np.maximum(w[seg], 1)
    y = lo[seg, 1] + local // np.maximum(w[seg], 1)
    X = np.stack([x + 0.5, y + 0.5], axis=1)
    AB = B[seg] - A[seg]
    L2 = np.einsum("ij,ij->i", AB, AB)
    t = np.clip(np.einsum("ij,ij->i", X - A[seg], AB) / np.maximum(L2, 1e-12), 0.0, 1.0)
    d = np.linalg.norm(X - A[seg] - t[:, None] * AB, axis=1)
    r = r0[seg] + t * (r1[seg] - r0[seg])
    a = np.clip(r + 0.5 - d, 0.0, 1.0) * (o0[seg] + t * (o1[seg] - o0[seg]))
    keep = a > 0
    pix, a, owner = y[keep] * size + x[keep], a[keep], who[seg][keep]
    key = pix * (int(who.max()) + 1) + owner                # a stroke's own overlaps once: its largest
    order = np.argsort(key, kind="stable")
    key, a, pix = key[order], a[order], pix[order]
    first = np.flatnonzero(np.r_[True, key[1:] != key[:-1]])
    amax = np.maximum.reduceat(a, first)
    np.add.at(log_clear, pix[first], np.log1p(-np.minimum(amax, 0.999999)))


def downsample(img, res):
    k = img.shape[0] // res
    return img[:k * res, :k * res].reshape(res, k, res, k).mean(axis=(1, 3))


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


# --- pictures ---------------------------------------------------------------------------

def write_png(path, gray):
    """An 8-bit grey PNG of ``gray`` (0 black .. 1 white)."""
    img = (np.clip(gray, 0, 1) * 255 + 0.5).astype(np.uint8)
    h, w = img.shape
    raw = b"".join(b"\x00" + img[y].tobytes() for y in range(h))

    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 0, 0, 0, 0))
                + chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b""))
