"""Stroke layers on top of the outlines (MASSRIS section 7, Smarticles section 7):
hatching and cross-hatching along a flow field, strokes started from feature chains,
short general strokes centred on polygon centres, and stipples from the wander
behaviour's path points.

Lighting: with a light direction L, a point is lit by max(0, n.L). Strokes go where
the surface is shaded: below ``lower`` always, above ``upper`` never, and between them
(the penumbra) at random with a probability growing with the shade. A stroke is
shortened where it leaves the shaded region. Each point's radius and opacity follow
its shade (:func:`tone`): darker, thicker and blacker.
"""
import numpy as np

from . import smarticles as sm
from ..agents import steering as st
from .data import Stroke
from .visibility import split_visible_many, visible

FIELDS = ("dir1", "dir2", "contour", "axis", "level", "straight")


def lighting(normals, light_dir):
    L = np.asarray(light_dir, float)
    L = L / np.linalg.norm(L)
    return np.maximum(0.0, np.asarray(normals, float) @ L)


def chosen_for_shade(lit, lower, upper, rng):
    """Which points get a stroke: all below lower, none above upper, random between."""
    p = np.clip((upper - lit) / max(upper - lower, 1e-9), 0.0, 1.0)
    return rng.random(len(lit)) < p


def tone(shade, upper, radius, contrast=1.0):
    """Per-point radius and opacity from the shade (0 lit .. upper penumbra edge):
    contrast 0 gives a uniform radius and full opacity, 1 gives radius 0.5-1.5x and
    opacity 0.35-1 from the edge of the shade to its darkest."""
    dark = np.clip(1.0 - np.asarray(shade, float) / max(upper, 1e-9), 0.0, 1.0)
    c = float(np.clip(contrast, 0.0, 1.0))
    return radius * (1.0 + c * (dark - 0.5)), 1.0 - c * 0.65 * (1.0 - dark)


def direction_field(kind, axis=None, eye=None):
    """A flow field for smarticles: "dir1"/"dir2" principal directions, "axis" (a user
    axis projected on the surface), "level" (the level lines of that axis: across it on
    the surface, horizontal for the vertical axis), "contour" (tangent and across the
    view direction), or "straight" (keep the current heading: the path of the initial
    direction)."""
    if kind in ("dir1", "dir2"):
        return lambda P, N, c: np.asarray(c[kind])
    if kind in ("axis", "level"):
        if axis is None or not np.all(np.isfinite(axis)) or np.linalg.norm(axis) == 0:
            raise ValueError(f"the {kind} flow field needs a finite non-zero axis, got {axis!r}")
        if kind == "level":
            return lambda P, N, c: st.contour_field(N, np.broadcast_to(st.unit(np.asarray(axis, float)), N.shape))
        return lambda P, N, c: st.axis_field(N, axis)
    if kind == "contour":
        if eye is None:
            raise ValueError("the contour flow field needs the eye position")
        return lambda P, N, c: st.contour_field(N, st.unit(np.asarray(eye, float) - P))
    if kind == "straight":
        return lambda P, N, c: np.asarray(c["velocity"])
    raise ValueError(f"unknown flow field {kind!r}; one of {', '.join(FIELDS)}")


def spawn_flocks(starts, normals, headings, size, spacing, rng):
    """Flocks spawned around initial positions (Smarticles 4): ``size`` members per
    start, side by side across the heading at ``spacing`` with a small random
    displacement. Returns positions, headings and flock ids."""
    starts, normals = np.asarray(starts, float), np.asarray(normals, float)
    if size <= 1 or len(starts) == 0:
        return starts, headings, np.arange(len(starts))
    side = st.unit(np.cross(normals, headings))
    offs = (np.arange(size) - 0.5 * (size - 1)) * spacing
    P = starts[:, None, :] + offs[None, :, None] * side[:, None, :]
    P = P + 0.25 * spacing * rng.normal(size=P.shape)
    H = np.repeat(headings, size, axis=0)
    return P.reshape(-1, 3), H, np.repeat(np.arange(len(starts)), size)


def shaded_strokes(ev, res, eye, light, upper, radius, region=None, contrast=1.0, min_points=2):
    """Smarticle paths as strokes: cut where they leave the shade (or the region),
    split where they go out of sight (one batched visibility test), toned by the shade."""
    kept = []
    for path, nrm in zip(res.paths, res.normals):
        shade = lighting(nrm, light)
        inside = shade <= upper
        if region is not None:
            inside &= region.contains(path)
        cut = len(path) if inside.all() else int(np.argmin(inside))    # shortened where it leaves the shade
        if cut >= min_points:
            kept.append((path[:cut], nrm[:cut], shade[:cut]))
    runs = split_visible_many(ev, [k[0] for k in kept], eye, [k[1] for k in kept], min_points)
    out = []
    for (path, nrm, shade), rr in zip(kept, runs):
        for a, b in rr:
            r, o = tone(shade[a:b], upper, radius, contrast)
            out.append(Stroke(path[a:b], r, o))
    return out


def hatching(ev, starts, start_normals, eye, light, step, rng, field="dir1", axis=(0, 0, 1), lower=0.25,
             upper=0.6, weights=None, rules=None, radius=0.003, flock_size=1, region=None, contrast=1.0):
    """Hatching strokes from the start points that fall in shade, following a flow
    field; with ``flock_size`` > 1 each chosen start spawns a flock (every
    flock_size-th chosen start, so the density stays alike)."""
    lit = lighting(start_normals, light)
    pick = np.flatnonzero(chosen_for_shade(lit, lower, upper, rng))[::max(1, flock_size)]
    P, N = np.asarray(starts, float)[pick], np.asarray(start_normals, float)[pick]
    rules = rules or sm.StrokeRules(max_steps=10, region=region)
    flow = direction_field(field, axis, eye)
    H = _initial_flow(ev, P, flow) if (field == "straight" or flock_size > 1) and len(P) else None
    flock = np.arange(len(P))
    if flock_size > 1 and len(P):
        P, H, flock = spawn_flocks(P, N, H, flock_size, 1.5 * step, rng)
    res = sm.run(ev, P, flow, step, weights or sm.PRESETS["hatching"], rules, rng, flock=flock, headings=H)
    return shaded_strokes(ev, res, eye, light, upper, radius, rules.region, contrast)


def chain_strokes(ev, outlines, eye, light, step, rng, every=3, angle=90.0, field="straight", axis=(0, 0, 1),
                  max_distance=None, lower=0.25, upper=0.6, weights=None, max_steps=12, radius=0.003,
                  region=None, contrast=1.0, features=None):
    """Strokes started from feature chains (Smarticles 7.2): every ``every``-th point
    of each outline starts a smarticle heading at ``angle`` degrees to the chain,
    towards the viewer for silhouettes (the visible side) and to both sides of a
    crease; strokes end at ``max_distance`` from the feature lines (default 4 steps): the
    points of ``features`` (default: these outlines' own)."""
    every = int(every)
    if every < 1:
        raise ValueError(f"the chain density step must be at least 1, got {every}")
    P, N, H = [], [], []
    feat = []
    for o in outlines:
        pts, nrm = np.asarray(o.points, float), np.asarray(o.normals, float)
        feat.append(pts)
        if len(pts) < 2:
            continue
        T = st.unit(np.gradient(pts, axis=0))
        across = st.unit(np.cross(nrm, T))
        a = np.radians(angle)
        head = st.unit(np.cos(a) * T + np.sin(a) * across)
        sel = slice(0, len(pts), every)
        p, n, h = pts[sel], nrm[sel], head[sel]
        if o.kind == "silhouette":
            flip = np.einsum("ij,ij->i", h, np.asarray(eye, float) - p) < 0
            h[flip] *= -1.0
            P.append(p)
            N.append(n)
            H.append(h)
        else:
            P += [p, p]
            N += [n, n]
            H += [h, -h]
    if not P:
        return []
    P, N, H = np.concatenate(P), np.concatenate(N), np.concatenate(H)
    pick = chosen_for_shade(lighting(N, light), lower, upper, rng)
    P, H = P[pick], H[pick]
    # start just off the line, on the chosen side, so the first step is not on the crease itself
    P = P + 0.5 * step * H
    dist = 4.0 * step if max_distance is None else float(max_distance)
    rules = sm.StrokeRules(max_steps=max_steps, stop_on_curvature_sign=False, max_normal_angle=np.radians(75),
                           feature_points=np.concatenate(feat) if features is None else np.asarray(features, float),
                           max_feature_distance=dist, region=region)
    res = sm.run(ev, P, direction_field(field, axis, eye), step, weights or sm.PRESETS["hatching"], rules, rng,
                 headings=H)
    return shaded_strokes(ev, res, eye, light, upper, radius, region, contrast)


def short_strokes(ev, centres, centre_normals, eye, light, step, rng, field="dir1", axis=(0, 0, 1), steps=3,
                  lower=0.3, upper=0.65, weights=None, radius=0.003, region=None, contrast=1.0):
    """Short general strokes centred on polygon centres (MASSRIS 7): from each chosen
    centre a smarticle goes ``steps`` steps each way along the flow field; the two
    halves make one stroke through the centre."""
    lit = lighting(centre_normals, light)
    C = np.asarray(centres, float)[chosen_for_shade(lit, lower, upper, rng)]
    if len(C) == 0:
        return []
    flow = direction_field(field, axis, eye)
    rules = sm.StrokeRules(max_steps=steps, stop_on_curvature_sign=False, max_normal_angle=np.radians(60),
                           region=region)
    w = weights or sm.PRESETS["hatching"]
    H = _initial_flow(ev, C, flow)
    fwd = sm.run(ev, C, flow, step, w, rules, rng, headings=H)
    bwd = sm.run(ev, C, flow, step, w, rules, rng, headings=-H)
    whole = sm.Run()
    for pf, nf, pb, nb in zip(fwd.paths, fwd.normals, bwd.paths, bwd.normals):
        whole.paths.append(np.vstack([pb[:0:-1], pf]))
        whole.normals.append(np.vstack([nb[:0:-1], nf]))
    return shaded_strokes(ev, whole, eye, light, upper, radius, region, contrast, min_points=3)


def stipples(ev, starts, start_normals, eye, light_dir, step, rng, every=3, steps=30, lower=0.2, upper=0.55,
             radius=0.004, region=None, contrast=1.0):
    """One-point strokes at every ``every``-th step of wandering smarticles in shade."""
    every = int(every)
    if every < 1:
        raise ValueError(f"the stipple step must be at least 1, got {every}")
    lit = lighting(start_normals, light_dir)
    starts = np.asarray(starts)[chosen_for_shade(lit, lower, upper, rng)]
    rules = sm.StrokeRules(max_steps=steps, max_normal_angle=np.radians(80), stop_on_curvature_sign=False,
                           region=region)
    res = sm.run(ev, starts, direction_field("dir1"), step, sm.PRESETS["stipple"], rules, rng)
    if not res.paths:
        return []
    D = np.concatenate([p[::every] for p in res.paths])
    Nn = np.concatenate([n[::every] for n in res.normals])
    shade = lighting(Nn, light_dir)
    keep = shade <= upper
    if region is not None:
        keep &= region.contains(D)
    D, Nn, shade = D[keep], Nn[keep], shade[keep]
    vis = visible(ev, D, eye, Nn)
    r, o = tone(shade[vis], upper, radius, contrast)
    return [Stroke(p[None], r[i:i + 1], o[i:i + 1], dots=True) for i, p in enumerate(D[vis])]


def _initial_flow(ev, P, flow):
    """The flow field's direction at points (for headings and flock spawning)."""
    from ..model.curvature import curvature
    f, g = ev.field_grad(P)
    c = curvature(ev, P, g)
    c["velocity"] = np.zeros_like(P)
    d = flow(P, c["normal"], c)
    if not np.any(np.linalg.norm(d, axis=1) > 0):       # "straight" has no field of its own
        d = c["dir1"]
    return st.unit(st.tangent(d, c["normal"]))
