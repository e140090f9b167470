"""Marks: points on the surface that belong to the model itself, where stroke layers
start (hatching, short strokes, stipples). A frame's marks depend on that frame's model
alone, and a mark on a part that moves rigidly moves with it.

Each primitive carries a low-discrepancy sequence (Halton, bases 2 and 3) laid out
area-uniformly on its own iso-surface in its own coordinates: a sphere around a point,
a capsule around a segment, a torus around a circle, a flattened capsule around a disc,
the faces of a box grown by the radius. The first n = area / spacing^2 points of the
sequence are taken (a prefix: a coarser spacing keeps a subset, a slightly larger area
adds points at the end and removes none), carried into the model's coordinates through
the warps above the primitive, and moved along the primitive's outward direction onto
the model's surface (a blend's surface lies outside its parts' own surfaces; a bracket
and bisection, as Newton steps alone stall where a difference makes the field flat). A mark is kept
only where its primitive owns the surface (model.owners): where primitives overlap,
each part of the surface keeps the marks of the one primitive that makes it.

Every mark has a key (its primitive's number and its index in the sequence, hashed), so
anything decided at random about a mark (model.keyed) is the same in every frame, and a
reference direction that turns with its primitive (to orient strokes the same way).
"""
from dataclasses import dataclass

import numpy as np

from . import keyed
from .owners import Owners
from .skins import Shape, unit
from .projection import project
from .tolerances import NEAR_SURFACE, on_surface

BRACKET_STEPS = 6              # samples along a mark's direction to bracket the model's surface
BISECTIONS = 8                 # ... then halvings of the bracket
FINISH_STEPS = 4               # ... then Newton steps onto it
MAX_MARKS = 4_000_000          # candidates of one call, at most (memory)
AREA_SAMPLES = 1500            # candidates that measure the surface's area
REFERENCE = np.array([1.0, 0.6, 0.35])      # a primitive's local reference direction (generic)


@dataclass(frozen=True)
class Marks:
    """Marks on the surface: points and normals (n, 3), ``keys`` (uint64), ``prim`` and
    ``index`` (the primitive's number and the mark's place in its sequence, from 1),
    ``area`` (the primitive's surface area in the model, for thinning) and ``ref``
    (unit reference directions turning with the primitive)."""
    points: np.ndarray
    normals: np.ndarray
    keys: np.ndarray
    prim: np.ndarray
    index: np.ndarray
    area: np.ndarray
    ref: np.ndarray

    def __len__(self):
        return len(self.points)

    def take(self, sel):
        return Marks(*(getattr(self, f)[sel] for f in self.__dataclass_fields__))

    def thinned(self, spacing):
        """The marks of a coarser ``spacing`` (a prefix of each primitive's sequence)."""
        return self.take(self.index <= np.rint(self.area / (spacing * spacing)))


def surface_marks(ev, spacing, salt=0, owners=None):
    """The marks of an evaluator's model at ``spacing`` (model units); ``salt`` picks
    another, independent set (another layer's)."""
    if not (np.isfinite(spacing) and spacing > 0):
        raise ValueError(f"the marks' spacing must be a positive number, got {spacing!r}")
    owners = owners if owners is not None else Owners(ev.model)
    s2 = spacing * spacing
    shapes = [(i, placed, Shape(placed.node, ev.iso)) for i, placed in enumerate(owners.placed)]
    counts = [int(np.rint(shape.area * placed.area_scale() / s2)) for _, placed, shape in shapes]
    if sum(counts) > MAX_MARKS:
        raise ValueError(f"a spacing of {spacing:g} asks for more than {MAX_MARKS} marks on the model: "
                         "the spacing is too small for its size")
    # first the primitives' own areas; then as many more marks as the surface they
    # reached is larger (a blend's surface lies outside its parts' own)
    first = _candidates(ev, shapes, [(1, n) for n in counts], salt)
    owned = owners.of(first.points) == first.prim
    sums = np.bincount(first.prim[owned], first.stretch[owned], len(shapes))
    found = np.bincount(first.prim[owned], minlength=len(shapes))
    stretch = np.where(found > 0, sums / np.maximum(found, 1), 1.0)     # over the marks a primitive keeps
    more = [int(np.rint(n * st)) for n, st in zip(counts, stretch)]
    if sum(more) > MAX_MARKS:
        raise ValueError(f"a spacing of {spacing:g} asks for more than {MAX_MARKS} marks on the model: "
                         "the spacing is too small for its size")
    second = _candidates(ev, shapes, [(n + 1, m) for n, m in zip(counts, more)], salt)
    c = first.joined(second)
    keep = np.concatenate([owned, owners.of(second.points) == second.prim])
    keep &= c.index <= np.asarray(more, np.int64)[c.prim]       # a smaller stretch takes fewer
    c = c.take(keep)
    area = np.array([shape.area * placed.area_scale() for _, placed, shape in shapes]) * stretch
    N = -unit(c.grad)
    ref = c.ref - np.einsum("ij,ij->i", c.ref, N)[:, None] * N
    return Marks(c.points, N, keyed.mark_keys(c.prim, c.index, salt), c.prim, c.index, area[c.prim], unit(ref))


def surface_area(ev, owners=None, samples=AREA_SAMPLES):
    """The area of the model's surface (:func:`surface_measures`)."""
    return surface_measures(ev, owners, samples)[0]


def surface_measures(ev, owners=None, samples=AREA_SAMPLES):
    """The area of the model's surface and its centre (the mean of its points, by
    area), from about ``samples`` candidates laid out as the marks are: each primitive's
    share of its own surface that it keeps, times how much that share grew on the way
    out. A part that moves without meeting others keeps its share exactly, so the area
    (and the line width and stroke lengths made from it) stays put, and moving or turning
    the whole model moves its centre with it."""
    owners = owners if owners is not None else Owners(ev.model)
    shapes = [(i, placed, Shape(placed.node, ev.iso)) for i, placed in enumerate(owners.placed)]
    own = np.array([shape.area * placed.area_scale() for _, placed, shape in shapes])
    if not len(own) or own.sum() <= 0:
        return 0.0, None
    s2 = own.sum() / samples
    counts = np.maximum(np.rint(own / s2).astype(np.int64), 1)
    c = _candidates(ev, shapes, [(1, n) for n in counts], 0)
    kept = owners.of(c.points) == c.prim
    w = (own / counts)[c.prim[kept]] * c.stretch[kept]
    centre = (w[:, None] * c.points[kept]).sum(0) / w.sum() if w.sum() > 0 else None
    return float(w.sum()), centre


@dataclass(frozen=True)
class _Found:
    """Candidates carried onto the model's surface: points, reference directions, the
    primitive and sequence index of each, the field's gradient there, and the area
    stretch from its primitive's own surface to where it landed."""
    points: np.ndarray
    ref: np.ndarray
    prim: np.ndarray
    index: np.ndarray
    grad: np.ndarray
    stretch: np.ndarray

    def take(self, sel):
        return _Found(*(getattr(self, f)[sel] for f in self.__dataclass_fields__))

    def joined(self, other):
        return _Found(*(np.concatenate([getattr(self, f), getattr(other, f)]) for f in self.__dataclass_fields__))


def _candidates(ev, shapes, ranges, salt):
    """The sequence points ``ranges[i] = (first, last)`` of each primitive, carried into
    the model and onto its surface (those that found it)."""
    parts = []
    for (i, placed, shape), (a, b) in zip(shapes, ranges):
        if b < a:
            continue
        k = np.arange(a, b + 1, dtype=np.int64)
        Q = shape.points(halton(k, shift=keyed.uniform(np.array([i], np.uint64), salt, count=2)[0]))
        h = 1e-4 * max(shape.reach, 1e-12)
        n = len(k)
        # the points, and a step along the primitive's outward direction and along its reference
        P, out, ref = np.split(placed.to_model(np.concatenate([Q, Q + h * shape.normals(Q), Q + h * REFERENCE])), 3)
        out, ref = out - P, ref - P
        scale = np.sqrt(placed.area_scale())
        parts.append((P, unit(out), ref, np.full(n, i, np.int64), k, np.full(n, scale * placed.node.radius),
                      np.full(n, scale * shape.d), shape.growth(Q)))
    if not parts:
        z = np.zeros((0, 3))
        return _Found(z, z, np.zeros(0, np.int64), np.zeros(0, np.int64), z, np.zeros(0))
    P0, out, ref, prim, index, reach, d, alpha = (np.concatenate(c) for c in zip(*parts))
    P, ok = _onto(ev, P0, out, reach)
    P, f, g = project(ev, P[ok], FINISH_STEPS)
    t = np.einsum("ij,ij->i", P - P0[ok], out[ok])           # how far out each went
    stretch = np.clip((d[ok] + t) / np.maximum(d[ok], 1e-300), 0.25, 4.0) ** alpha[ok]
    on = on_surface(f, ev.iso, NEAR_SURFACE) & (np.linalg.norm(g, axis=1) > 0)
    return _Found(P, ref[ok], prim[ok], index[ok], g, stretch).take(on)


def _onto(ev, P0, out, reach):
    """Each point moved along its direction ``out`` to where the field crosses iso,
    within ``reach``: the way along it where the field goes towards iso (outward from
    inside a part; inward from inside a subtracted part's hollow, whose field grows
    outwards), the crossing bracketed in BRACKET_STEPS samples, then bisected. Returns
    the points and whether a crossing was found."""
    iso = ev.iso
    f0, g0 = ev.field_grad(P0)
    rising = np.einsum("ij,ij->i", g0, out) > 0       # the field grows along out (a subtracted part)
    side = np.where(f0 >= iso, 1.0, -1.0)              # inside (1) or outside (-1) the solid
    step = (reach / BRACKET_STEPS) * side * np.where(rising, -1.0, 1.0)
    lo = np.zeros(len(P0))
    hi = np.full(len(P0), np.nan)
    live = np.flatnonzero(f0 != iso)
    for k in range(1, BRACKET_STEPS + 1):
        if len(live) == 0:
            break
        t = k * step[live]
        f = ev.field(P0[live] + t[:, None] * out[live])
        crossed = (f - iso) * side[live] <= 0
        hi[live[crossed]] = t[crossed]
        lo[live[~crossed]] = t[~crossed]
        live = live[~crossed]
    ok = np.isfinite(hi) | (f0 == iso)
    hi = np.where(f0 == iso, 0.0, hi)
    idx = np.flatnonzero(ok & (f0 != iso))
    a, b = lo[idx], hi[idx]
    for _ in range(BISECTIONS):
        m = 0.5 * (a + b)
        f = ev.field(P0[idx] + m[:, None] * out[idx])
        inside = (f - iso) * side[idx] > 0
        a, b = np.where(inside, m, a), np.where(inside, b, m)
    t = np.zeros(len(P0))
    t[idx] = 0.5 * (a + b)
    return P0 + t[:, None] * out, ok


def _empty():
    z3 = np.zeros((0, 3))
    zi = np.zeros(0, np.int64)
    return Marks(z3, z3, np.zeros(0, np.uint64), zi, zi, np.zeros(0), z3)


def radical_inverse(k, base):
    k = np.array(k, np.int64)
    out = np.zeros(len(k))
    f = 1.0 / base
    while np.any(k > 0):
        out += f * (k % base)
        k //= base
        f /= base
    return out


def halton(k, shift=(0.0, 0.0)):
    """(n, 2) Halton points (bases 2, 3) of indices k, shifted modulo 1 (Cranley-Patterson:
    another set as well spread)."""
    return np.stack([(radical_inverse(k, 2) + shift[0]) % 1.0, (radical_inverse(k, 3) + shift[1]) % 1.0], axis=1)
