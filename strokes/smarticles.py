"""Smarticles: particles that place strokes by steering and flocking on the iso-surface
(Smarticles sections 5 and 7; MASSRIS section 7).

A run starts smarticles at given points (one per stroke; a flock is a group sharing a
flock id), steps them all together (one batched field evaluation per step), corrects
them onto the surface, and ends each path on the termination rules: a change of the
sign of the mean curvature, the normal turning from the start's by more than a limit,
path length or step count, the distance from a feature line (the closest point of
the given feature points), or leaving the containment region. The terminating point
is not included.
"""
from dataclasses import dataclass, field

import numpy as np

from ..model import keyed
from ..model.curvature import curvature, tangent_basis
from ..model.projection import project
from ..model.tolerances import NEAR_SURFACE, on_surface
from ..agents import steering as st
from ..model.vectors import cross

PRESETS = {
    # Smarticles 7.2: parallel strokes want separation and alignment over cohesion
    "hatching": {"flow": 1.0, "wander": 0.0, "separation": 0.0, "alignment": 0.0, "cohesion": 0.0},
    "flock": {"flow": 1.0, "wander": 0.15, "separation": 0.6, "alignment": 0.5, "cohesion": 0.05},
    "sketchy": {"flow": 0.7, "wander": 0.5, "separation": 0.3, "alignment": 0.3, "cohesion": 0.1},
    "stipple": {"flow": 0.0, "wander": 1.0, "separation": 0.0, "alignment": 0.0, "cohesion": 0.0},
}


@dataclass
class StrokeRules:
    max_steps: int = 40
    max_length: float = np.inf
    max_normal_angle: float = np.radians(60.0)
    stop_on_curvature_sign: bool = True
    region: object = None                  # agents.Region or None
    feature_points: object = None          # (m, 3) points of the feature lines, or None
    max_feature_distance: float = np.inf   # containment around those feature lines
    stop: object = None                    # a further rule: stop(ids, before, after, normals) -> (ends, values)


@dataclass
class Run:
    paths: list = field(default_factory=list)      # (k, 3) arrays
    normals: list = field(default_factory=list)
    reasons: list = field(default_factory=list)
    values: list = field(default_factory=list)     # (k,) arrays: what a further rule measured at each point


def run(ev, starts, direction_field, step, weights, rules, keys, flock=None, separation_radius=None,
        headings=None, target=None, path=None, start_values=None, bends=True):
    """Trace one path per start. ``direction_field(P, normals, curv) -> (n,3)`` gives
    the flow field (e.g. a principal direction; ``curv["velocity"]`` is the current
    heading, for fields that keep it). ``keys`` (n,) are the smarticles' own keys
    (model.keyed): their random wander is theirs, whatever else runs with them.
    ``headings`` (n,3) are the initial headings (by default the flow field at the
    start). Behaviours with targets: "seek" steers to ``target``, "path" follows the
    polyline ``path``, "containment" steers back into ``rules.region`` before leaving it."""
    P = np.array(starts, float)
    n = len(P)
    out = Run()
    if n == 0:
        return out
    keys = np.asarray(keys, np.uint64)
    if keys.shape != (n,):
        raise ValueError(f"one key per start: {n} starts, keys of shape {keys.shape}")
    flock = np.zeros(n, int) if flock is None else np.asarray(flock)
    P, f, g = project(ev, P, START_STEPS)
    N = -st.unit(g)
    bends = bends or rules.stop_on_curvature_sign
    carried = CARRIED if bends else ()
    c = curvature(ev, P, g) if bends else {"dir1": tangent_basis(N)[0]}
    c["velocity"] = np.zeros_like(P)
    V = np.array(direction_field(P, N, c) if headings is None else headings, float).reshape(n, 3)
    T = st.tangent(V, N)
    # no heading in the tangent plane (a field that only keeps the heading has none at the start): dir1
    flat = np.linalg.norm(T, axis=1) <= 1e-9 * np.linalg.norm(V, axis=1)
    T[flat] = c["dir1"][flat]
    V = st.unit(T)
    start_n = N.copy()
    start_sign = np.sign(c["mean"]) if bends else None
    alive = on_surface(f, ev.iso, NEAR_SURFACE)        # a start that did not reach the surface draws nothing
    # the points (and normals) kept, a batch a step: whose they are, in step order
    first = np.flatnonzero(alive)
    owner, points, normals = [first], [P[first]], [N[first]]
    values = [np.zeros(n)[first] if start_values is None else np.asarray(start_values, float)[first]]
    reasons = np.where(alive, "", "lost surface").astype(object)
    lengths = np.zeros(n)
    sep_r = separation_radius if separation_radius is not None else 2 * step
    for k in range(rules.max_steps):
        idx = np.flatnonzero(alive)
        if len(idx) == 0:
            break
        p, v, nn = P[idx], V[idx], N[idx]
        cur = {key: c[key][idx] for key in carried}
        cur.update(normal=nn, velocity=v)
        forces = {"flow": st.flow(direction_field(p, nn, cur), v)} if weights.get("flow", 0) else {}
        if weights.get("wander", 0):
            forces["wander"] = st.wander(v, nn, _noise(keys[idx], k, nn, v))
        if weights.get("seek", 0):
            if target is None:
                raise ValueError("the seek behaviour needs a target")
            forces["seek"] = st.seek(p, target)
        if weights.get("path", 0):
            if path is None or len(path) < 2:
                raise ValueError("the path-following behaviour needs a path of at least two points")
            forces["path"] = st.path_following(p, v, path, 0.5 * step, 2.0 * step)
        if weights.get("containment", 0) and rules.region is not None:
            forces["containment"] = st.containment(p, v, rules.region, 2.0 * step)
        if any(weights.get(w, 0) for w in ("separation", "alignment", "cohesion")):
            forces["separation"] = st.separation(p, flock[idx], sep_r) * step ** 2
            forces["alignment"] = st.alignment(v, flock[idx])
            forces["cohesion"] = st.cohesion(p, flock[idx]) / max(step, 1e-300)
        F = st.combine(forces, weights)
        F = st.tangent(F, nn)
        newp, newv = st.integrate(p, v, F, 1.0, step)
        newp, fq, gq = _onto(ev, newp)
        nq = -st.unit(gq)
        cq = curvature(ev, newp, gq) if bends else None
        stop = np.zeros(len(idx), bool)
        why = np.array([""] * len(idx), object)
        ang = np.arccos(np.clip(np.einsum("ij,ij->i", nq, start_n[idx]), -1, 1))
        m = ang > rules.max_normal_angle
        stop |= m
        why[m] = "normal angle"
        if rules.stop_on_curvature_sign:
            m = (np.sign(cq["mean"]) != start_sign[idx]) & ~stop
            stop |= m
            why[m] = "curvature sign"
        seg = np.linalg.norm(newp - p, axis=1)
        m = (lengths[idx] + seg > rules.max_length) & ~stop
        stop |= m
        why[m] = "length"
        if rules.feature_points is not None and np.isfinite(rules.max_feature_distance):
            m = (nearest_distance(newp, rules.feature_points) > rules.max_feature_distance) & ~stop
            stop |= m
            why[m] = "feature distance"
        if rules.region is not None:
            m = ~rules.region.contains(newp) & ~stop
            stop |= m
            why[m] = "left region"
        m = ~on_surface(fq, ev.iso, NEAR_SURFACE) & ~stop
        stop |= m
        why[m] = "lost surface"
        val = np.zeros(len(idx))
        if rules.stop is not None:
            ends, measured = rules.stop(idx, p, newp, nq)
            m = np.asarray(ends, bool) & ~stop
            stop |= m
            why[m] = "rule"
            if measured is not None:
                val = np.asarray(measured, float)
        ended = idx[stop]
        alive[ended] = False               # the terminating point is not included
        reasons[ended] = why[stop]
        go = idx[~stop]
        owner.append(go)
        points.append(newp[~stop])
        normals.append(nq[~stop])
        values.append(val[~stop])
        P[go], V[go], N[go] = newp[~stop], st.tangent(newv[~stop], nq[~stop]), nq[~stop]
        lengths[go] += seg[~stop]
        for key in carried:
            c[key][go] = cq[key][~stop]
    owner = np.concatenate(owner)
    order = np.argsort(owner, kind="stable")    # path by path, each in step order
    ends = np.cumsum(np.bincount(owner, minlength=n)).tolist()
    spans = list(zip([0] + ends[:-1], ends))
    P, N = np.concatenate(points)[order], np.concatenate(normals)[order]
    V = np.concatenate(values)[order]
    out.paths = [P[a:b] for a, b in spans]
    out.normals = [N[a:b] for a, b in spans]
    out.values = [V[a:b] for a, b in spans]
    out.reasons = [r or "steps" for r in reasons.tolist()]
    return out


def both_ways(ev, starts, headings, keys, direction_field, step, weights, rules, flock=None, values=None,
              separation_radius=None):
    """Smarticles set off from each start both ways (its heading and the opposite, the
    second's key combined with 1), their two paths joined at the start: per start k whose
    smarticles both moved, (k, points, normals, values along them or None, the start's
    row). ``values`` (n,): what each start carries (strokes.smarticles.Run.values)."""
    P = np.asarray(starts, float).reshape(-1, 3)
    H = np.asarray(headings, float).reshape(-1, 3)
    n = len(P)
    flock = np.arange(n) if flock is None else np.asarray(flock)
    both = run(ev, np.vstack([P, P]), direction_field, step, weights, rules,
               np.concatenate([keys, keyed.combine(keys, 1)]), headings=np.vstack([H, -H]), bends=False,
               flock=np.concatenate([flock, flock + n]), separation_radius=separation_radius,
               start_values=None if values is None else np.concatenate([values, values]))
    lines = []
    for k in range(n):
        fwd, bwd = both.paths[k], both.paths[n + k]
        if len(fwd) == 0 or len(bwd) == 0:
            continue
        pts = np.vstack([bwd[:0:-1], fwd])
        nrm = np.vstack([both.normals[n + k][:0:-1], both.normals[k]])
        val = None if values is None else np.concatenate([both.values[n + k][:0:-1], both.values[k]])
        lines.append((k, pts, nrm, val, len(bwd) - 1))
    return lines


def run_kept(paths, ev, starts, direction_field, step, weights, rules, keys, flock=None, headings=None, bends=True):
    """:func:`run`, with the paths of the keys found in ``paths`` (a dict key -> (path,
    normals, reason), or None) taken from it and the others run and put in it: a
    smarticle's path depends on its key, its start and heading and the model alone for
    flow fields that do not look at the eye (the caller keeps such a dict per model and
    per set of rules). A flock's members are all kept or all run (their keys come and go
    together)."""
    if paths is None:
        return run(ev, starts, direction_field, step, weights, rules, keys, flock=flock, headings=headings, bends=bends)
    keys = np.asarray(keys, np.uint64)
    ids = keys.tolist()
    todo = np.array([k not in paths for k in ids], bool)
    if todo.any():
        P = np.asarray(starts, float).reshape(-1, 3)
        got = run(ev, P[todo], direction_field, step, weights, rules, keys[todo],
                  flock=None if flock is None else np.asarray(flock)[todo],
                  headings=None if headings is None else np.asarray(headings, float)[todo], bends=bends)
        for k, p, n, r in zip(keys[todo].tolist(), got.paths, got.normals, got.reasons):
            paths[k] = (p, n, r)
    return kept(paths, keys)


def kept(paths, keys):
    """The Run of these smarticles' paths when ``paths`` (:func:`run_kept`'s dict) holds
    every one of them, else None (then nothing about them needs to be known to run them:
    their starts and headings)."""
    if paths is None:
        return None
    ids = np.asarray(keys, np.uint64).tolist()
    if not all(k in paths for k in ids):
        return None
    out = Run()
    for k in ids:
        p, n, r = paths[k]
        out.paths.append(p)
        out.normals.append(n)
        out.reasons.append(r)
    return out


WANDER = 7              # the salt of the wander's noise (model.keyed)
CARRIED = ("mean", "k1", "k2", "dir1", "dir2")      # the curvature a flow field may read


def _noise(keys, k, normals, vel):
    """Each smarticle's standard normal 3-vector for step k, in its own frame (its
    heading, the direction across it on the surface, the normal): the same relative to
    the surface wherever the surface is moved or turned."""
    z = keyed.normal(keys, WANDER, k, count=3)
    d1 = st.unit(st.tangent(vel, normals))
    d2 = cross(normals, d1)
    return z[:, :1] * d1 + z[:, 1:2] * d2 + z[:, 2:] * normals


def nearest_distance(P, Q, rows=512):
    """Distance from each point of P (n,3) to the closest point of Q (m,3), in row
    blocks so that memory stays bounded."""
    P, Q = np.asarray(P, float), np.asarray(Q, float)
    if len(Q) == 0:
        return np.full(len(P), np.inf)
    qq = np.einsum("ij,ij->i", Q, Q)
    out = np.empty(len(P))
    for a in range(0, len(P), rows):
        p = P[a:a + rows]
        d2 = np.einsum("ij,ij->i", p, p)[:, None] + qq[None, :] - 2.0 * p @ Q.T
        out[a:a + rows] = np.sqrt(np.maximum(d2.min(axis=1), 0.0))
    return out


ONTO_STEPS = 4             # Newton steps of the attractor correction after each move
START_STEPS = 8            # ... and onto the surface from the starts (a flock's members start off it)


def _onto(ev, P):
    """Attractor correction onto f = iso (Smarticles: F = (f(x) - iso) grad f(x)), as
    Newton steps along the gradient (model.projection, the agents' projection)."""
    return project(ev, P, ONTO_STEPS)
