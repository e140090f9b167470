"""What the stroke layers (MASSRIS section 7, Smarticles section 7) share: the flow
fields the smarticles follow, the headings they set off along, flocks, and the seeds on
the feature chains. The layers themselves: strokes.hatching (hatching, cross-hatching,
strokes from the feature chains, short strokes), strokes.stipples.

Hatching, short strokes and stipples start at marks (model.marks): points that belong
to the model's primitives, so a frame's strokes follow the parts they are on. Whatever
is random about a mark's stroke (a flock's places, the wander) is drawn from its key
(model.keyed), not from a run's generator.
"""
import numpy as np

from ..agents import steering as st
from ..model import keyed
from ..model.curvature import curvature
from ..model.projection import project
from ..model.tolerances import NEAR_SURFACE, on_surface
from ..model.vectors import cross

FIELDS = ("dir1", "dir2", "diagonal", "contour", "axis", "level", "straight")
TURN = np.radians(45.0)      # a principal direction this far from a smarticle's heading is noise
ISOTROPIC = 0.2         # principal directions count where (k1 - k2) exceeds this share of |k1| + |k2|
FLOCK_PLACE = 3         # where a flock's member starts (a salt of what is decided about a mark, model.keyed)


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
    start, side by side across the heading at ``spacing`` (one, or one per start), each displaced a little by
    its own key (model.keyed) in the frame of the heading. Returns positions, headings,
    flock ids and the members' keys."""
    starts, normals = np.asarray(starts, float), np.asarray(normals, float)
    keys = np.asarray(keys, np.uint64)
    if size <= 1 or len(starts) == 0:
        return starts, headings, np.arange(len(starts)), keys
    side = st.unit(cross(normals, headings))
    spacing = np.broadcast_to(np.asarray(spacing, float), (len(starts),))[:, None]      # (one per start)
    offs = (np.arange(size) - 0.5 * (size - 1))[None, :] * spacing
    P = starts[:, None, :] + offs[:, :, None] * side[:, None, :]
    members = flock_keys(keys, size)
    z = keyed.normal(members, FLOCK_PLACE, count=3).reshape(len(starts), size, 3)
    frame = np.stack([headings, side, normals], axis=1)             # (n, 3 axes, 3)
    P = P + 0.25 * spacing[:, :, None] * np.einsum("nma,nak->nmk", z, frame)
    H = np.repeat(headings, size, axis=0)
    return P.reshape(-1, 3), H, np.repeat(np.arange(len(starts)), size), members


def flock_keys(keys, size):
    """The keys of the members of the flocks the marks of ``keys`` spawn (:func:`spawn_flocks`)."""
    keys = np.asarray(keys, np.uint64)
    return keys if size <= 1 else keyed.combine(keys[:, None], np.arange(size)[None, :]).reshape(-1)


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


def chain_seeds(outlines, eye, every=3, angle=90.0):
    """Where strokes start from feature chains (Smarticles 7.2): every ``every``-th point of
    each outline (with its normal), heading at ``angle`` degrees to the chain, towards
    the viewer for a silhouette (its visible side) and to both sides of a crease.
    Returns points, normals and headings."""
    every = int(every)
    if every < 1:
        raise ValueError(f"the chain density step must be at least 1, got {every}")
    P, N, H = [], [], []
    a = np.radians(angle)
    for o in outlines:
        pts, nrm = np.asarray(o.points, float), np.asarray(o.normals, float)
        if len(pts) < 2:
            continue
        T = st.unit(np.gradient(pts, axis=0))
        head = st.unit(np.cos(a) * T + np.sin(a) * st.unit(cross(nrm, T)))
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
        return np.zeros((0, 3)), np.zeros((0, 3)), np.zeros((0, 3))
    return np.concatenate(P), np.concatenate(N), np.concatenate(H)


CHAIN_TILTS = (0.0, 45.0, -45.0, 80.0, -80.0)   # degrees into the surface a chain seed's step is tried at
CHAIN_ONTO = 4              # Newton steps that put a chain stroke's start, just off its line, onto the surface
BEYOND = 0.25               # a chain seed has landed beyond its line when it went this share of its step along
                            # its heading ...
ASTRAY = 3.0                # ... and no farther than this many steps from its chain point


def off_the_chain(ev, P0, N0, H0, off):
    """Chain seeds (:func:`chain_seeds`: points on a feature line, its normal there, a
    heading off it) moved ``off`` off the line onto the surface on their side (a point on
    a silhouette grazes its own surface), heading away from the line. A crease's far
    side is another sheet, at an angle to the line's normal (a cup's inner wall below
    its rim, a union's other part above the valley): where a step along the heading does
    not land beyond the line, steps tilted into and out of the surface (CHAIN_TILTS) are
    tried. Returns points, normals and headings of the seeds that landed."""
    n = len(P0)
    P, N, H, found = np.zeros((n, 3)), np.zeros((n, 3)), np.zeros((n, 3)), np.zeros(n, bool)
    for tilt in CHAIN_TILTS:
        todo = np.flatnonzero(~found)
        if len(todo) == 0:
            break
        t = np.radians(tilt)
        Q, f, g = project(ev, P0[todo] + off * (np.cos(t) * H0[todo] - np.sin(t) * N0[todo]), CHAIN_ONTO)
        Nq = -g / np.maximum(np.linalg.norm(g, axis=1, keepdims=True), 1e-300)
        gone = Q - P0[todo]
        away = gone - np.einsum("ij,ij->i", gone, Nq)[:, None] * Nq          # (in the landed point's tangent plane)
        ok = on_surface(f, ev.iso, NEAR_SURFACE) & (np.einsum("ij,ij->i", gone, H0[todo]) > BEYOND * off)
        ok &= (np.linalg.norm(gone, axis=1) < ASTRAY * off) & (np.linalg.norm(away, axis=1) > 1e-6 * off)
        P[todo[ok]], N[todo[ok]], H[todo[ok]], found[todo[ok]] = Q[ok], Nq[ok], away[ok], True
    H = H[found]
    return P[found], N[found], H / np.linalg.norm(H, axis=1, keepdims=True)
