"""Stroke layers on top of the outlines (MASSRIS section 7, Smarticles section 7):
hatching and cross-hatching along principal directions (or an axis) in shaded
regions, and stipples from the wander behaviour's path points.

Lighting: with a light direction L, a point is lit by max(0, n.L). Strokes go where
the surface is shaded: below ``upper`` always... above it never, and between ``lower``
and ``upper`` (the penumbra) at random with a probability growing with the shade. A
stroke is shortened where it leaves the shaded region.
"""
import numpy as np

from . import smarticles as sm
from . import steering as st
from .data import Stroke
from .visibility import split_visible


def lighting(normals, light_dir):
    L = np.asarray(light_dir, float)
    L = L / np.linalg.norm(L)
    return np.maximum(0.0, normals @ L)


def chosen_for_shade(lit, lower, upper, rng):
    """Which points get a stroke: all below lower, none above upper, random between."""
    p = np.clip((upper - lit) / max(upper - lower, 1e-9), 0.0, 1.0)
    return rng.random(len(lit)) < p


def direction_field(kind, axis=None):
    """A flow field for smarticles: "dir1"/"dir2" principal directions, or "axis"."""
    if kind in ("dir1", "dir2"):
        return lambda P, N, c: np.asarray(c[kind])
    if kind == "axis":
        return lambda P, N, c: st.axis_field(N, axis)
    raise ValueError(f"unknown flow field {kind!r}; dir1, dir2 or axis")


def hatching(ev, starts, start_normals, eye, light_dir, step, rng, field="dir1", axis=(0, 0, 1),
             lower=0.25, upper=0.6, preset="hatching", max_steps=10, radius=0.003, weights=None, rules=None):
    """Hatching strokes from the start points that fall in shade, cut where they leave
    the shade and where they go out of sight."""
    lit = lighting(start_normals, light_dir)
    pick = chosen_for_shade(lit, lower, upper, rng)
    starts = np.asarray(starts)[pick]
    rules = rules or sm.StrokeRules(max_steps=max_steps)
    res = sm.run(ev, starts, direction_field(field, axis), step, weights or sm.PRESETS[preset], rules, rng,
                 flock=np.arange(len(starts)) // 4)
    out = []
    for path, nrm in zip(res.paths, res.normals):
        shade = lighting(nrm, light_dir)
        inside = shade <= upper
        if rules.region is not None:
            inside &= rules.region.contains(path)
        cut = len(path) if inside.all() else int(np.argmin(inside))    # shortened where it leaves the shade
        path, nrm, shade = path[:cut], nrm[:cut], shade[:cut]
        if len(path) < 2:
            continue
        for a, b in split_visible(ev, path, eye, nrm):
            k = b - a
            dark = np.clip(1.0 - shade[a:b] / max(upper, 1e-9), 0.25, 1.0)
            out.append(Stroke(path[a:b], np.full(k, radius), dark))
    return out


def stipples(ev, starts, start_normals, eye, light_dir, step, rng, every=3, steps=30, lower=0.2, upper=0.55,
             radius=0.004, region=None):
    """One-point strokes at every ``every``-th step of wandering smarticles in shade."""
    lit = lighting(start_normals, light_dir)
    starts = np.asarray(starts)[chosen_for_shade(lit, lower, upper, rng)]
    rules = sm.StrokeRules(max_steps=steps, max_normal_angle=np.radians(80), stop_on_curvature_sign=False,
                           region=region)
    res = sm.run(ev, starts, direction_field("dir1"), step, sm.PRESETS["stipple"], rules, rng)
    dots, normals = [], []
    for path, nrm in zip(res.paths, res.normals):
        dots.append(path[::every])
        normals.append(nrm[::every])
    if not dots:
        return []
    D = np.concatenate(dots)
    Nn = np.concatenate(normals)
    keep = lighting(Nn, light_dir) <= upper
    if region is not None:
        keep &= region.contains(D)
    D, Nn = D[keep], Nn[keep]
    from .visibility import visible
    vis = visible(ev, D, eye, Nn)
    return [Stroke(p[None], np.array([radius]), np.array([1.0]), dots=True) for p in D[vis]]
