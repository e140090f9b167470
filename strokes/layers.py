"""Stroke layers on top of the outlines (MASSRIS section 7, Smarticles section 7):
hatching and cross-hatching along a flow field, strokes started from feature chains,
short general strokes (stipples, from the wander behaviour's path points: strokes.stipples).

Hatching, short strokes and stipples start at marks (model.marks): points that belong
to the model's primitives, so a frame's strokes follow the parts they are on. Whatever
is random about a mark's stroke (whether a mark in the penumbra gets one, a flock's
places, the wander) is drawn from its key (model.keyed), not from a run's generator.

Lighting: with a light direction L, a point is lit by max(0, n.L). Strokes go where
the surface is shaded: below ``lower`` always, above ``upper`` never, and between them
(the penumbra) at random with a probability growing with the shade. A stroke is
shortened where it leaves the shaded region; a hatching stroke where it leaves its
own share of it, its light limit drawn from its mark between ``upper`` and FRAYED of
the penumbra below it, so the hatching's edge towards the light frays out instead of
ending in a row of cut ends. Each point's radius and opacity follow its shade
(:func:`tone`): darker, thicker and blacker.
"""
import numpy as np

from . import smarticles as sm
from ..agents import steering as st
from ..model import keyed
from ..model.curvature import curvature
from ..model.vectors import cross
from .data import Stroke
from .visibility import piece, run_points, visible_runs

FIELDS = ("dir1", "dir2", "diagonal", "contour", "axis", "level", "straight")
TURN = np.radians(45.0)      # a principal direction this far from a smarticle's heading is noise
ISOTROPIC = 0.2         # principal directions count where (k1 - k2) exceeds this share of |k1| + |k2|
# salts of what is decided about a mark (model.keyed)
SHADE = 1               # whether a mark in the penumbra gets a stroke
FLOCK = 2               # whether a mark spawns a flock
FLOCK_PLACE = 3         # where a flock's member starts
BACKWARDS = 4           # the smarticle of a short stroke's other half
FRAY = 5                # where a hatching stroke leaves the shade
FRAYED = 0.5            # hatching strokes end between the penumbra's top and this share of it below


def lighting(normals, light_dir):
    L = np.asarray(light_dir, float)
    L = L / np.linalg.norm(L)
    return np.maximum(0.0, np.asarray(normals, float) @ L)


def chosen_for_shade(lit, lower, upper, u):
    """Which points get a stroke: all below lower, none above upper, between them those
    whose own uniform number ``u`` (a mark's, model.keyed) is below the shade's share."""
    p = np.clip((upper - lit) / max(upper - lower, 1e-9), 0.0, 1.0)
    return np.asarray(u) < p


def tone(shade, upper, radius, contrast=1.0):
    """Per-point radius and opacity from the shade (0 lit .. upper penumbra edge):
    contrast 0 gives a uniform radius and full opacity, 1 gives radius 0.5-1.5x and
    opacity 0.35-1 from the edge of the shade to its darkest."""
    dark = np.clip(1.0 - np.asarray(shade, float) / max(upper, 1e-9), 0.0, 1.0)
    c = float(np.clip(contrast, 0.0, 1.0))
    return radius * (1.0 + c * (dark - 0.5)), 1.0 - c * 0.65 * (1.0 - dark)


def direction_field(kind, axis=None, eye=None):
    """A flow field for smarticles: "dir1"/"dir2" principal directions, "diagonal" (half
    way between them: dir1 turned 45 degrees about the normal, towards dir2), "axis" (a user
    axis projected on the surface), "level" (the level lines of that axis: across it on
    the surface, horizontal for the vertical axis), "contour" (tangent and across the
    view direction), or "straight" (keep the current heading: the path of the initial
    direction). Where the surface bends alike every way (:func:`isotropic`) the
    principal directions are noise: a smarticle keeps its heading there."""
    if kind in ("dir1", "dir2", "diagonal"):
        def principal(P, N, c):
            d = np.array(c[kind], float) if kind != "diagonal" else st.unit(np.asarray(c["dir1"]) + c["dir2"])
            v = c["velocity"]
            moving = np.linalg.norm(v, axis=1) > 0
            # no direction of its own, or one across the heading (the two principal directions
            # changing places near an umbilic within a step): go on
            across = np.abs(np.einsum("ij,ij->i", d, v)) < np.cos(TURN) * np.linalg.norm(v, axis=1)
            keep = (isotropic(c) | across) & moving
            d[keep] = st.unit(v[keep])            # a direction as strong as a principal one
            return d
        return principal
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
        return lambda P, N, c: st.unit(np.asarray(c["velocity"], float))
    raise ValueError(f"unknown flow field {kind!r}; one of {', '.join(FIELDS)}")


def spawn_flocks(starts, normals, headings, size, spacing, keys):
    """Flocks spawned around initial positions (Smarticles 4): ``size`` members per
    start, side by side across the heading at ``spacing``, each displaced a little by
    its own key (model.keyed) in the frame of the heading. Returns positions, headings,
    flock ids and the members' keys."""
    starts, normals = np.asarray(starts, float), np.asarray(normals, float)
    keys = np.asarray(keys, np.uint64)
    if size <= 1 or len(starts) == 0:
        return starts, headings, np.arange(len(starts)), keys
    side = st.unit(cross(normals, headings))
    offs = (np.arange(size) - 0.5 * (size - 1)) * spacing
    P = starts[:, None, :] + offs[None, :, None] * side[:, None, :]
    members = flock_keys(keys, size)
    z = keyed.normal(members, FLOCK_PLACE, count=3).reshape(len(starts), size, 3)
    frame = np.stack([headings, side, normals], axis=1)             # (n, 3 axes, 3)
    P = P + 0.25 * spacing * np.einsum("nma,nak->nmk", z, frame)
    H = np.repeat(headings, size, axis=0)
    return P.reshape(-1, 3), H, np.repeat(np.arange(len(starts)), size), members


def flock_keys(keys, size):
    """The keys of the members of the flocks the marks of ``keys`` spawn (:func:`spawn_flocks`)."""
    keys = np.asarray(keys, np.uint64)
    return keys if size <= 1 else keyed.combine(keys[:, None], np.arange(size)[None, :]).reshape(-1)


def shaded_strokes(ev, res, eye, light, upper, radius, region=None, contrast=1.0, min_points=2, keys=None,
                   sight=None, lower=None):
    """Smarticle paths as strokes: cut where they leave the shade (or the region; with
    ``lower`` and ``keys``, each where it leaves its own share of the shade,
    :func:`limits`), split where they go out of sight (one batched visibility test
    against ``sight``, a strokes.visibility.Sight: default the model's own solid
    alone), toned by the shade; each stroke keeps its smarticle's key (``keys``) as its
    mark. All paths' points are lit, cut and toned together."""
    if not res.paths:
        return []
    sizes = np.array([len(p) for p in res.paths])
    P = np.concatenate([np.asarray(p, float).reshape(-1, 3) for p in res.paths])
    N = np.concatenate([np.asarray(n, float).reshape(-1, 3) for n in res.normals])
    shade = lighting(N, light)
    inside = shade <= (upper if lower is None or keys is None else np.repeat(limits(keys, lower, upper), sizes))
    if region is not None:
        inside &= region.contains(P)
    # each path shortened where it first leaves the shade
    first = np.cumsum(sizes) - sizes
    local = np.arange(len(P)) - np.repeat(first, sizes)
    cut = sizes.copy()
    some = sizes > 0
    if some.any():
        cut[some] = np.minimum.reduceat(np.where(inside, np.repeat(sizes, sizes), local), first[some])
    kept = cut >= min_points
    take = (local < np.repeat(cut, sizes)) & np.repeat(kept, sizes)
    P, N, shade = P[take], N[take], shade[take]
    sizes = cut[kept]
    at = np.cumsum(sizes) - sizes
    r, o = tone(shade, upper, radius, contrast)
    marks = [None] * len(sizes) if keys is None else np.asarray(keys)[kept].tolist()
    out = []
    for k, runs in enumerate(visible_runs(ev if sight is None else sight, P, sizes, eye, N, min_points)):
        for run in runs:
            run = run._replace(a=at[k] + run.a, b=at[k] + run.b)
            out.append(Stroke(run_points(P, run), piece(r, run), piece(o, run),
                              mark=None if marks[k] is None else int(marks[k])))
    return out


def limits(keys, lower, upper):
    """The light at which each hatching stroke (by its smarticle's key) ends: from
    ``upper`` down to FRAYED of the penumbra (``lower`` to ``upper``) below it."""
    return upper - FRAYED * (upper - lower) * keyed.uniform(np.asarray(keys, np.uint64), FRAY)


def hatching(ev, marks, eye, light, step, field="dir1", axis=(0, 0, 1), lower=0.25, upper=0.6, weights=None,
             rules=None, radius=0.003, flock_size=1, region=None, contrast=1.0, salt=0, paths=None,
             every_path=False, crowding=None, sight=None):
    """Hatching strokes from the marks (model.marks) that fall in shade, following a
    flow field, each heading the way its mark's reference direction says; with
    ``flock_size`` > 1 one mark in flock_size (by its key) spawns a flock, so the
    density stays alike. ``salt``: another layer's choices (cross-hatching); ``paths``:
    the smarticles' paths kept for these rules (smarticles.run_kept), and with
    ``every_path`` those of every mark are made in it, in shade or not (a model seen in
    frame after frame: the light and the eye then only choose among them);
    ``crowding``: a :class:`strokes.crowding.Crowding` that thins the strokes where they
    run into knots of the layer's strokes so far on the paper, or None; ``sight``: as for
    :func:`shaded_strokes`."""
    flocks = np.ones(len(marks), bool)
    if flock_size > 1:
        flocks = keyed.uniform(marks.keys, salt, FLOCK) * flock_size < 1.0
    rules = rules or sm.StrokeRules(max_steps=10, region=region)
    flow = direction_field(field, axis, eye)
    w = weights or sm.PRESETS["hatching"]

    def own(m):
        return m.keys if salt == 0 else keyed.combine(m.keys, salt)     # cross-hatching's strokes are others

    def run(m):
        keys = flock_keys(own(m), flock_size)
        res = sm.kept(paths, keys)
        if res is None:
            H = headings(ev, m.points, field, m.ref, axis, eye)
            P, H, flock, keys = spawn_flocks(m.points, m.normals, H, flock_size, 1.5 * step, own(m))
            res = sm.run_kept(paths, ev, P, flow, step, w, rules, keys, flock=flock, headings=H)
        return res, keys
    if every_path and paths is not None:
        run(marks.take(flocks))
    lit = lighting(marks.normals, light)
    res, keys = run(marks.take(flocks & chosen_for_shade(lit, lower, upper, keyed.uniform(marks.keys, salt, SHADE))))
    out = shaded_strokes(ev, res, eye, light, upper, radius, rules.region, contrast, keys=keys, sight=sight,
                         lower=lower)
    return out if crowding is None else crowding.thinned(out)


def chain_strokes(ev, outlines, eye, light, step, rng, every=3, angle=90.0, field="straight", axis=(0, 0, 1),
                  max_distance=None, lower=0.25, upper=0.6, weights=None, max_steps=12, radius=0.003,
                  region=None, contrast=1.0, features=None, sight=None):
    """Strokes started from feature chains (Smarticles 7.2): every ``every``-th point
    of each outline starts a smarticle heading at ``angle`` degrees to the chain,
    towards the viewer for silhouettes (the visible side) and to both sides of a
    crease; strokes end at ``max_distance`` from the feature lines (default 4 steps): the
    points of ``features`` (default: these outlines' own). The outlines' points are no
    marks: the choices in the penumbra and the smarticles' keys come from ``rng``
    (``sight``: as for :func:`shaded_strokes`)."""
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
        across = st.unit(cross(nrm, T))
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
    pick = chosen_for_shade(lighting(N, light), lower, upper, rng.random(len(N)))
    P, H = P[pick], H[pick]
    # start just off the line, on the chosen side, so the first step is not on the crease itself
    P = P + 0.5 * step * H
    dist = 4.0 * step if max_distance is None else float(max_distance)
    rules = sm.StrokeRules(max_steps=max_steps, stop_on_curvature_sign=False, max_normal_angle=np.radians(75),
                           feature_points=np.concatenate(feat) if features is None else np.asarray(features, float),
                           max_feature_distance=dist, region=region)
    keys = rng.integers(0, 1 << 63, len(P), dtype=np.int64).astype(np.uint64)
    res = sm.run(ev, P, direction_field(field, axis, eye), step, weights or sm.PRESETS["hatching"], rules, keys,
                 headings=H)
    return shaded_strokes(ev, res, eye, light, upper, radius, region, contrast, sight=sight)


def short_strokes(ev, marks, eye, light, step, field="dir1", axis=(0, 0, 1), steps=3, lower=0.3, upper=0.65,
                  weights=None, radius=0.003, region=None, contrast=1.0, paths=None, every_path=False, sight=None):
    """Short general strokes centred on the marks (MASSRIS 7 centres them on polygons):
    from each chosen mark a smarticle goes ``steps`` steps each way along the flow
    field; the two halves make one stroke through the mark (``paths``, ``every_path``:
    as for :func:`hatching`; ``sight``: as for :func:`shaded_strokes`)."""
    flow = direction_field(field, axis, eye)
    rules = sm.StrokeRules(max_steps=steps, stop_on_curvature_sign=False, max_normal_angle=np.radians(60),
                           region=region)
    w = weights or sm.PRESETS["hatching"]

    def run(m):
        back = keyed.combine(m.keys, BACKWARDS)
        fwd, bwd = sm.kept(paths, m.keys), sm.kept(paths, back)
        if fwd is None or bwd is None:
            H = headings(ev, m.points, field, m.ref, axis, eye)
            fwd = sm.run_kept(paths, ev, m.points, flow, step, w, rules, m.keys, headings=H)
            bwd = sm.run_kept(paths, ev, m.points, flow, step, w, rules, back, headings=-H)
        return fwd, bwd
    if every_path and paths is not None:
        run(marks)
    lit = lighting(marks.normals, light)
    m = marks.take(chosen_for_shade(lit, lower, upper, keyed.uniform(marks.keys, SHADE)))
    if len(m) == 0:
        return []
    fwd, bwd = run(m)
    whole = sm.Run()
    for pf, nf, pb, nb in zip(fwd.paths, fwd.normals, bwd.paths, bwd.normals):
        whole.paths.append(np.vstack([pb[:0:-1], pf]))
        whole.normals.append(np.vstack([nb[:0:-1], nf]))
    return shaded_strokes(ev, whole, eye, light, upper, radius, region, contrast, min_points=3, keys=m.keys,
                          sight=sight)


def isotropic(c):
    """Where the principal directions mean nothing: the principal curvatures differ by
    less than ISOTROPIC of their size (near umbilics, on flat parts), or are not known."""
    k1, k2 = np.asarray(c["k1"]), np.asarray(c["k2"])
    return ~(np.abs(k1 - k2) > ISOTROPIC * (np.abs(k1) + np.abs(k2)))


def headings(ev, P, kind, ref, axis=None, eye=None):
    """The flow field's direction at points, each turned to agree with its reference
    direction (``ref``: a mark's, which turns with its primitive), so a stroke sets off
    the same way in every frame; where a field that follows the principal directions has
    none (:func:`isotropic`), along the reference direction itself."""
    if len(P) == 0:
        return np.zeros((0, 3))
    f, g = ev.field_grad(P)
    c = curvature(ev, P, g)
    c["velocity"] = np.zeros_like(P)
    N = c["normal"]
    H = direction_field(kind, axis, eye)(P, N, c)
    flat = ~(np.linalg.norm(H, axis=1) > 0)                 # "straight" has no field of its own
    H[flat] = c["dir1"][flat]
    if kind in ("dir1", "dir2", "diagonal", "straight"):
        weak = isotropic(c)
        H[weak] = ref[weak]
    H = st.unit(st.tangent(H, N))
    s = np.sign(np.einsum("ij,ij->i", H, ref))
    s[s == 0] = 1.0
    return H * s[:, None]
