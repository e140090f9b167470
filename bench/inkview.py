"""What the quality measures look at (pure numpy), shared by bench/quality.py and the
core tests: a camera framed as the command line frames its picture, the exact surface
ray cast from it (the lit target, what is hidden), and a drawing's strokes rasterised.
The figures computed from them: bench/inkmeasure.py.

    cam = Camera.framing(eye, centre, points, size=1024)
    lit = cast_light(ev, cam, light, res=256)           # Lambert with cast shadows, NaN off the model
    ink = rasterise(cam, strokes, 1024)                 # the ink's coverage, 0..1
"""
import struct
import zlib

import numpy as np

from blobtree_ink.blackboard.polygonise import surface_box
from blobtree_ink.pipeline.framing import MARGIN, crop
from blobtree_ink.strokes import tone as TN

MARCH = 0.002           # ray-march step, a share of the model's support diagonal


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
