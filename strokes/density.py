"""How dark a hatching layer's lines make each patch of the paper against what the tone
asks there, and the gain that evens them out (Vanderhaeghe et al. 2007: marks fixed on
the object, density decided on the screen). A map's lines stand evenly on the surface
and each is drawn as wide as its tone asks (strokes.hatching.widths), but where they are
cut short (wrinkles, knots of the field, small parts), left out (scraps, blots, pieces
out of sight) or crowd, a patch gets less or more ink than its tone: a first drawing of
every line is measured on a grid of the paper against the tone of the surface that rays
from the eye meet there, both smoothed, and their ratio (GAIN at most either way) scales
the coverage each point of the lines asks in the drawing itself.
"""
from dataclasses import dataclass

import numpy as np

from . import tone as TN
from ..model.projection import project
from .hatching import _turning
from .visibility import first_hits, visible

CELL = 0.5              # the grid's cells: this share of level 0's spacing across (on the paper)
SMOOTH = 2.0            # ink and tone are smoothed by a Gaussian of this many cells before their ratio is taken,
TRUNCATE = 3.0          # cut off at this many of its sigmas (the grid is padded as far beyond the lines)
MOST_CELLS = 250_000    # a grid of more cells (a model seen from very near) takes wider ones
WIDEN = 1.01            # ... each round of widening the cells a little past the share that should do
WIDEN_ROUNDS = 32       # ... in at most this many rounds (the pad's cells stay: a few do)
NEAREST = 0.05          # a map point nearer the eye than this share of the paper's distance is not measured
GAIN = 2.0              # a point's coverage is scaled by at most this, or at least its inverse
RAY_STEP = 4e-3         # the rays that sample the tone step this share of the model's scale
ONTO = 2                # Newton steps that put a ray's hit onto the surface (one that moves it farther than a
                        # ray's step went astray: not a sample)
FAINT = 1e-3            # a smoothed tone below this asks nothing: no gain there


@dataclass
class Gain:
    """A gain on a grid of the paper: cell (0, 0)'s centre at ``origin``, ``cell`` wide,
    ``grid`` (rows along y, columns along x); 1 off the grid."""
    origin: np.ndarray
    cell: float
    grid: np.ndarray

    def at(self, places):
        """The gain at places on the paper (n, 2 or 3), bilinear between cell centres."""
        u = (np.asarray(places, float)[:, :2] - self.origin) / self.cell
        ny, nx = self.grid.shape
        out = np.ones(len(u))
        inside = (u[:, 0] >= 0) & (u[:, 0] <= nx - 1) & (u[:, 1] >= 0) & (u[:, 1] <= ny - 1)
        x, y = u[inside, 0], u[inside, 1]
        i, j = np.minimum(np.floor(y).astype(np.int64), ny - 2), np.minimum(np.floor(x).astype(np.int64), nx - 2)
        fy, fx = y - i, x - j
        g = self.grid
        out[inside] = ((1 - fy) * ((1 - fx) * g[i, j] + fx * g[i, j + 1])
                       + fy * ((1 - fx) * g[i + 1, j] + fx * g[i + 1, j + 1]))
        return out


def _blur(img, sigma):
    r = int(np.ceil(TRUNCATE * sigma))
    k = np.exp(-0.5 * (np.arange(-r, r + 1) / sigma) ** 2)
    k /= k.sum()
    img = np.apply_along_axis(lambda v: np.convolve(v, k, "same"), 0, img)
    return np.apply_along_axis(lambda v: np.convolve(v, k, "same"), 1, img)


def ink(paper, strokes, origin, cell, shape):
    """The share of each cell of a grid of the paper that the strokes cover: each
    segment as long and as wide (its ends' mean) as it is on the paper, in the cell of
    its middle."""
    out = np.zeros(shape)
    for s in strokes:
        xy, scale = paper.place(s.points)
        if len(xy) < 2:
            continue
        length = np.linalg.norm(np.diff(xy[:, :2], axis=0), axis=1)
        wide = (s.radius * scale)[:-1] + (s.radius * scale)[1:]             # twice the mean radius
        mid = 0.5 * (xy[1:, :2] + xy[:-1, :2])
        ij = np.round((mid - origin) / cell).astype(np.int64)
        ok = (ij[:, 0] >= 0) & (ij[:, 0] < shape[1]) & (ij[:, 1] >= 0) & (ij[:, 1] < shape[0])
        np.add.at(out, (ij[ok, 1], ij[ok, 0]), length[ok] * wide[ok])
    return out / cell ** 2


def asked(layer, origin, cell, shape, within=None):
    """The coverage the layer's tone asks at each cell's centre: of the surface a ray from
    the eye first meets there, where it faces the eye (by more than the layer's turning),
    lies in the layer's region, on the surface its lines are drawn on (``within``, a
    function of points: the style's convex or concave parts; default all) and in sight;
    0 elsewhere."""
    paper, ev = layer.paper, layer.ev
    ys, xs = np.mgrid[0:shape[0], 0:shape[1]]
    xy = origin + cell * np.column_stack([xs.ravel(), ys.ravel()])
    D = np.column_stack([xy, np.full(len(xy), paper.reach)]) @ paper.axes.T
    D /= np.linalg.norm(D, axis=1, keepdims=True)
    X, hit = first_hits(ev, paper.eye, D, RAY_STEP * ev.scale)
    out = np.zeros(len(xy))
    rows = np.flatnonzero(hit)
    if len(rows) == 0:
        return out.reshape(shape)
    X0 = X[rows]
    X, _, g = project(ev, X0, ONTO)
    N = -g / np.maximum(np.linalg.norm(g, axis=1, keepdims=True), 1e-300)
    near = np.linalg.norm(X - X0, axis=1) <= RAY_STEP * ev.scale          # (within the step the hit is past it)
    ok = near & ~_turning(paper, X, N, layer.turning)
    if layer.rules.region is not None:
        ok &= layer.rules.region.contains(X)
    if within is not None and ok.any():
        ok[ok] = within(X[ok])
    if ok.any() and getattr(layer.sight, "others", ()):
        ok[ok] = visible(layer.sight, X[ok], paper.eye, N[ok])
    out[rows[ok]] = TN.coverage(layer.tone(X[ok], N[ok]), layer.share)
    return out.reshape(shape)


def measure(layer, hmap, strokes, within=None):
    """The :class:`Gain` that evens a layer's ``strokes`` (a first drawing of its map
    ``hmap``'s lines, before their ends are spread) out against its tone (``within``: as
    :func:`asked`), on a grid over the places of the map's points that face the eye, in
    front of it; cells half a spacing wide, or wider where that would make more than
    MOST_CELLS. Where the smoothed tone asks less than FAINT the gain is 1."""
    paper = layer.paper
    P = hmap.points
    depth = (P - paper.eye) @ paper.axes[:, 2]
    use = (depth > NEAREST * paper.reach) & ~_turning(paper, P, hmap.normals, layer.turning)
    if layer.rules.region is not None and use.any():
        use[use] = layer.rules.region.contains(P[use])
    cell = CELL * hmap.spacing
    if not use.any() or not cell > 0:
        return Gain(np.zeros(2), 1.0, np.ones((2, 2)))
    q = paper.place(P[use])[0][:, :2]
    pad = int(np.ceil(TRUNCATE * SMOOTH))
    span = q.max(axis=0) - q.min(axis=0)
    for _ in range(WIDEN_ROUNDS):
        cells = float(np.prod(np.ceil(span / cell) + 2 * pad + 2))
        if cells <= MOST_CELLS:
            break
        cell *= WIDEN * float(np.sqrt(cells / MOST_CELLS))
    lo = np.floor(q.min(axis=0) / cell) - pad
    hi = np.ceil(q.max(axis=0) / cell) + pad
    origin = lo * cell
    shape = (int(hi[1] - lo[1]) + 1, int(hi[0] - lo[0]) + 1)
    want = _blur(asked(layer, origin, cell, shape, within), SMOOTH)
    got = _blur(ink(paper, strokes, origin, cell, shape), SMOOTH)
    with np.errstate(divide="ignore", invalid="ignore"):
        g = np.where(got > 0, want / got, GAIN)
    g = np.where(want > FAINT, np.clip(g, 1.0 / GAIN, GAIN), 1.0)
    return Gain(origin, cell, g)
