"""Hidden-line removal against the exact iso-surface (not the rough polygonisation).

A point is visible when the segment from it to the eye does not enter the solid
(f >= iso). Segments are marched in one batch: each starts a small offset off the
surface towards the eye, is clipped to the surface's box (blackboard.polygonise.
surface_box: outside it the field stays below iso), and is sampled at a fixed fraction
of the model's size. Strokes are split where
visibility changes and the hidden parts dropped.
"""
import numpy as np

from ..blackboard.polygonise import surface_box


MARCH_BATCH = 4096          # points a ray-march call aims at
MAX_AHEAD = 32              # samples of one ray a call takes at most


def _clip(O, D, lo, hi):
    """Parameter range [t0, t1] of rays O + t D (t in [0, 1]) inside the box."""
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = 1.0 / D
        ta = (lo - O) * inv
        tb = (hi - O) * inv
    tmin = np.nanmax(np.where(np.isfinite(np.minimum(ta, tb)), np.minimum(ta, tb), -np.inf), axis=1)
    tmax = np.nanmin(np.where(np.isfinite(np.maximum(ta, tb)), np.maximum(ta, tb), np.inf), axis=1)
    inside_axis = (D == 0) & ((O < lo) | (O > hi))
    tmax = np.where(inside_axis.any(axis=1), -1.0, tmax)
    return np.maximum(tmin, 0.0), np.minimum(tmax, 1.0)


def visible(ev, P, eye, normals=None, step=None, offset=None):
    """Boolean visibility of points P (n,3) seen from eye."""
    P = np.asarray(P, float)
    if len(P) == 0:
        return np.zeros(0, bool)
    scale = ev.scale
    step = step if step is not None else 2e-3 * scale
    offset = offset if offset is not None else 2e-3 * scale
    to_eye = eye - P
    dist = np.linalg.norm(to_eye, axis=1)
    u = to_eye / dist[:, None]
    start = P + offset * u
    if normals is not None:
        start = start + 0.5 * offset * np.asarray(normals)
    D = eye - start
    box = surface_box(ev)                           # where f >= iso can be (else the support's)
    lo, hi = box if box is not None else ev.bounds
    t0, t1 = _clip(start, D, lo, hi)
    vis = np.ones(len(P), bool)
    live = np.flatnonzero(t1 > t0)
    length = np.linalg.norm(D, axis=1)
    k = 0
    while len(live):
        # the samples k, k+1, ... of each ray still marching, as many per ray as keep a
        # batch near MARCH_BATCH points (a call's cost is mostly its own: the last few
        # rays take their remaining samples in a few calls, not one call per sample)
        b = int(np.clip(MARCH_BATCH // len(live), 1, MAX_AHEAD))
        t = t0[live, None] + ((k + np.arange(b))[None, :] * step) / length[live, None]      # (m, b)
        inside = t <= t1[live, None]
        Q = (start[live, None, :] + t[:, :, None] * D[live, None, :]).reshape(-1, 3)
        if inside.all():                   # a sample a ray (always so when they take one each)
            f = ev.field(Q).reshape(t.shape)
        else:                              # the samples past a ray's end (its last call's tail) are not evaluated
            f = np.full(t.shape, -np.inf)
            f[inside] = ev.field(Q[inside.reshape(-1)])
        hit = f >= ev.iso
        vis[live[hit.any(axis=1)]] = False
        live = live[~hit.any(axis=1) & inside[:, -1]]
        k += b
    return vis


def split_visible(ev, stroke_points, eye, normals=None, min_points=2):
    """[(start, end)] index ranges of the visible runs of a polyline."""
    return split_visible_many(ev, [stroke_points], eye, None if normals is None else [normals], min_points)[0]


def split_visible_many(ev, polylines, eye, normals=None, min_points=2):
    """The visible runs of many polylines, marched as one batch (one field evaluation
    per ray-march step for all their points): a list of [(start, end)] per polyline."""
    if not polylines:
        return []
    sizes = np.array([len(p) for p in polylines])
    P = np.concatenate([np.asarray(p, float).reshape(-1, 3) for p in polylines])
    Nn = None if normals is None else np.concatenate([np.asarray(n, float).reshape(-1, 3) for n in normals])
    return visible_runs(ev, P, sizes, eye, Nn, min_points)


def visible_runs(ev, P, sizes, eye, normals=None, min_points=2):
    """:func:`split_visible_many` of polylines given as their points one after the other
    (``P``, with their ``normals``) and their lengths (``sizes``)."""
    return _runs(visible(ev, P, eye, normals), np.asarray(sizes, np.int64), min_points)


def _runs(v, sizes, min_points):
    """[(start, end)] of the True runs of v at least min_points long, per polyline
    (``sizes``: the polylines' lengths along v; a run never crosses from one to the
    next), found in one pass over all of them."""
    ends_at = np.cumsum(sizes)
    first = ends_at - sizes
    # a False between consecutive polylines, so no run crosses from one into the next
    gap = np.insert(v.astype(np.int8), ends_at, 0)
    gapped = first + np.arange(len(sizes))                   # each polyline's first point in ``gap``
    d = np.diff(np.concatenate([[0], gap, [0]]))
    starts, ends = np.flatnonzero(d == 1), np.flatnonzero(d == -1)
    keep = ends - starts >= min_points
    starts, ends = starts[keep], ends[keep]
    line = np.searchsorted(gapped, starts, "right") - 1
    starts, ends = (starts - gapped[line]).tolist(), (ends - gapped[line]).tolist()
    out = [[] for _ in sizes]
    for k, a, b in zip(line.tolist(), starts, ends):
        out[k].append((a, b))
    return out
