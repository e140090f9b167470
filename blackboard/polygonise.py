"""Rough polygonisation of the iso-surface: vectorised surface nets on a regular grid.

One vertex per surface cell (the mean of its edge crossings, each crossing found by
regula falsi along its grid edge, then moved onto the surface by a few Newton steps;
a cell whose mean cannot reach the surface takes one of its crossings), and one
quad per sign-changing grid edge joining the four cells around it, oriented so that
its normal points out of the solid (counter-clockwise seen from outside).
"""
from dataclasses import dataclass

import numpy as np

from ..model.projection import project
from ..model.tolerances import NEAR_SURFACE, on_surface
from .keys import unique_rows

MIN_RES, MAX_RES = 2, 512
LAYERS = 4               # sample layers per evaluation of the surface box's walks inwards


class GridError(ValueError):
    """A grid that cannot be built (bad resolution, empty bounds, too much memory)."""


@dataclass
class Grid:
    lo: np.ndarray        # (3,) corner of cell (0, 0, 0)
    cell: np.ndarray      # (3,) cell size
    res: tuple            # cells per axis
    field: np.ndarray     # (res+1)^3 corner field values

    def corner(self, ijk):
        return self.lo + np.asarray(ijk) * self.cell


@dataclass
class Mesh:
    vertices: np.ndarray  # (V, 3)
    quads: np.ndarray     # (F, 4) vertex indices, outward counter-clockwise
    cells: np.ndarray     # (V, 3) integer cell of each vertex
    grid: Grid

    def triangles(self):
        q = self.quads
        return np.concatenate([q[:, [0, 1, 2]], q[:, [0, 2, 3]]])

    def edges(self):
        """Unique undirected edges (E, 2) of the quads."""
        q = self.quads
        e = np.concatenate([q[:, [0, 1]], q[:, [1, 2]], q[:, [2, 3]], q[:, [3, 0]]])
        e = np.sort(e, axis=1)
        return unique_rows(e)


def surface_box(ev, res=48, pad_cells=1.5):
    """Bounds of the solid f >= iso, from a res^3 sampling of the support box (walked
    layer by layer inwards from its faces: see _surface_box); kept on the evaluator
    (whose plan is fixed), so that placing a view and polygonising, or a second run on
    one model, sample it once."""
    key = ("surface_box", int(res), float(pad_cells))
    if key not in ev.memo:
        ev.memo[key] = _surface_box(ev, res, pad_cells)
    box = ev.memo[key]
    return None if box is None else (box[0].copy(), box[1].copy())


def _surface_box(ev, res, pad_cells):
    """The inside extents of a res^3 sampling of the support box, found without
    sampling all of it: from each end of each axis, whole layers of samples are taken
    inwards (LAYERS per evaluation) up to the first that holds an inside sample. An
    axis taken after another only samples its layers within the other's extent,
    where every inside sample lies. The result is that of sampling every point."""
    lo, hi = ev.bounds
    if not (np.all(np.isfinite(lo)) and np.all(np.isfinite(hi)) and np.all(hi > lo)):
        return None
    axes = [np.linspace(lo[i], hi[i], res) for i in range(3)]
    win = [[0, res - 1] for _ in range(3)]
    for i in range(3):
        others = tuple(j for j in range(3) if j != i)
        for e, way in ((0, 1), (1, -1)):
            k = win[i][e]
            while True:
                layers = [x for x in range(k, k + way * LAYERS, way) if win[i][0] <= x <= win[i][1]]
                if not layers:
                    return None                       # no sample inside
                sub = [axes[j][win[j][0]:win[j][1] + 1] if j != i else axes[i][layers] for j in range(3)]
                on = np.flatnonzero(_inside(ev, sub).any(axis=others))
                if len(on):
                    win[i][e] = layers[int(on[0])]
                    break
                k += way * LAYERS
    cell = (hi - lo) / (res - 1)
    slo = np.array([axes[i][win[i][0]] for i in range(3)]) - pad_cells * cell
    shi = np.array([axes[i][win[i][1]] for i in range(3)]) + pad_cells * cell
    return np.maximum(slo, lo - cell), np.minimum(shi, hi + cell)


def _inside(ev, axes):
    X, Y, Z = np.meshgrid(*axes, indexing="ij")
    shape = X.shape
    return (ev.field(np.stack([X.ravel(), Y.ravel(), Z.ravel()], axis=1)) >= ev.iso).reshape(shape)


def sample_grid(ev, res, bounds=None, max_bytes=2 * 2**30):
    """Field at the corners of a cubic-cell grid of about res^3 cells over the bounds
    (default: the surface box); a cube gets res cells per side, a long model more
    along its length and fewer across (never more than 4 res along a side)."""
    if not isinstance(res, (int, np.integer)) or not MIN_RES <= res <= MAX_RES:
        raise GridError(f"grid resolution must be a whole number from {MIN_RES} to {MAX_RES}, got {res!r}")
    if bounds is None:
        bounds = surface_box(ev)
        if bounds is None:
            raise GridError("the model has no surface (its field never reaches iso)")
    lo, hi = (np.asarray(b, float) for b in bounds)
    ext = hi - lo
    if not np.all(np.isfinite(ext)) or np.any(ext <= 0):
        raise GridError(f"grid bounds must be finite and non-empty, got {lo} .. {hi}")
    # cubic cells, about res^3 of them over the box (a long thin model gets more cells
    # along its length, as a cube would), at most 4 res along any side
    h = max(float(np.prod(ext)) ** (1.0 / 3.0) / res, ext.max() / (4 * res))
    dims = np.maximum(np.ceil(ext / h - 1e-9).astype(int), 1)
    ncorner = int(np.prod(dims + 1))
    need = ncorner * 8 * 8     # corners, coordinates and temporaries
    if need > max_bytes:
        raise GridError(f"a grid of {dims[0]}x{dims[1]}x{dims[2]} cells needs about {need / 2**30:.1f} GiB; "
                        f"lower the resolution")
    lo = lo - (dims * h - ext) / 2
    axes = [lo[i] + h * np.arange(dims[i] + 1) for i in range(3)]
    X, Y, Z = np.meshgrid(*axes, indexing="ij")
    f = ev.field(np.stack([X.ravel(), Y.ravel(), Z.ravel()], axis=1)).reshape(tuple(dims + 1))
    return Grid(lo=lo, cell=np.full(3, h), res=tuple(int(d) for d in dims), field=f)


def polygonise(ev, res, bounds=None, project_steps=6):
    grid = sample_grid(ev, res, bounds)
    return mesh_from_grid(ev, grid, project_steps)


def refine_crossings(ev, A, B, fA, fB, iters=12, ftol=0.0):
    """Points where f = iso on the segments A-B (fA, fB on opposite sides of iso), by
    regula falsi with the Illinois rule, batched (field values only), each until its
    bracket is below 1e-9 of the segment or |f - iso| at most ``ftol``. A compact kernel
    is far from linear across a cell: linear interpolation alone can put a crossing
    outside the support or on the flat core of a primitive (f = 0 or 1, no gradient)."""
    iso = ev.iso
    a, b = fA - iso, fB - iso
    lo_t, hi_t = np.zeros(len(A)), np.ones(len(A))
    t = a / (a - b)
    last = np.zeros(len(A), np.int8)
    live = np.arange(len(A))
    for _ in range(iters):
        if len(live) == 0:
            break
        tl = np.clip(t[live], lo_t[live] + 1e-12, hi_t[live] - 1e-12)
        fm = ev.field(A[live] + tl[:, None] * (B[live] - A[live])) - iso
        t[live] = tl
        same_a = (fm >= 0) == (a[live] >= 0)
        ia, ib = live[same_a], live[~same_a]
        lo_t[ia], a[ia] = tl[same_a], fm[same_a]
        hi_t[ib], b[ib] = tl[~same_a], fm[~same_a]
        b[ia[last[ia] == 1]] *= 0.5
        a[ib[last[ib] == 2]] *= 0.5
        last[ia], last[ib] = 1, 2
        done = (np.abs(fm) <= ftol) | (hi_t[live] - lo_t[live] < 1e-9)
        live = live[~done]
        if len(live):
            t[live] = lo_t[live] + a[live] / (a[live] - b[live]) * (hi_t[live] - lo_t[live])
    return A + t[:, None] * (B - A)


def edge_ends(a):
    """Index tuples of the lower and upper corners of every grid edge along axis a."""
    sl0, sl1 = [slice(None)] * 3, [slice(None)] * 3
    sl0[a], sl1[a] = slice(0, -1), slice(1, None)
    return tuple(sl0), tuple(sl1)


def mesh_from_grid(ev, grid, project_steps=6):
    f, iso, h, lo = grid.field, ev.iso, grid.cell, grid.lo
    nx, ny, nz = grid.res
    inside = f >= iso
    edge_lists = []
    crossings = []
    for a in range(3):
        sl0, sl1 = edge_ends(a)
        f0, f1 = f[sl0], f[sl1]
        change = inside[sl0] != inside[sl1]
        ijk = np.argwhere(change)                      # lower corner of each crossing edge
        crossings.append((a, ijk, f0[change], f1[change]))
        edge_lists.append((a, ijk, inside[sl0][change]))
    # every crossing edge refined in one batch
    A = np.concatenate([lo + ijk * h for _, ijk, _, _ in crossings])
    step = np.concatenate([np.tile(np.eye(3)[a] * h, (len(ijk), 1)) for a, ijk, _, _ in crossings])
    fa = np.concatenate([c[2] for c in crossings])
    fb = np.concatenate([c[3] for c in crossings])
    refined = refine_crossings(ev, A, A + step, fa, fb) if project_steps else None
    start = 0
    flats, around = [], []                   # each crossing in the (up to) four cells around its edge
    for a, ijk, f0c, f1c in crossings:
        if refined is not None:
            pts = refined[start:start + len(ijk)]
        else:
            t = (iso - f0c) / (f1c - f0c)
            pts = lo + ijk * h
            pts[:, a] += t * h[a]
        start += len(ijk)
        b, c = (a + 1) % 3, (a + 2) % 3
        for db in (-1, 0):
            for dc in (-1, 0):
                cidx = ijk.copy()
                cidx[:, b] += db
                cidx[:, c] += dc
                ok = (cidx[:, b] >= 0) & (cidx[:, b] < grid.res[b]) & (cidx[:, c] >= 0) & (cidx[:, c] < grid.res[c])
                ok &= cidx[:, a] < grid.res[a]
                flats.append(np.ravel_multi_index(cidx[ok].T, grid.res))
                around.append(pts[ok])
    ncell = nx * ny * nz
    flat = np.concatenate(flats) if flats else np.zeros(0, np.int64)
    around = np.concatenate(around) if around else np.zeros((0, 3))
    count = np.bincount(flat, minlength=ncell)
    active = np.flatnonzero(count)           # in the order of np.argwhere over the cells
    cell_any = np.zeros((ncell, 3))          # one edge crossing of each cell
    cell_any[flat] = around
    cell_any = cell_any[active]
    cells = np.stack(np.unravel_index(active, grid.res), axis=1)
    vid = np.full(ncell, -1, np.int64)
    vid[active] = np.arange(len(active))
    vid = vid.reshape(grid.res)
    verts = np.stack([np.bincount(flat, weights=around[:, k], minlength=ncell)[active] for k in range(3)],
                     axis=1).astype(float)        # no crossing at all: bincount gives integers
    verts /= count[active][:, None]
    quads = []
    for a, ijk, low_inside in edge_lists:
        b, c = (a + 1) % 3, (a + 2) % 3          # (a, b, c) cyclic: b x c = +a
        ok = (ijk[:, b] >= 1) & (ijk[:, c] >= 1) & (ijk[:, b] < grid.res[b]) & (ijk[:, c] < grid.res[c])
        ok &= ijk[:, a] < grid.res[a]
        e, li = ijk[ok], low_inside[ok]

        def v(db, dc):
            cc = e.copy()
            cc[:, b] += db
            cc[:, c] += dc
            return vid[cc[:, 0], cc[:, 1], cc[:, 2]]
        q = np.stack([v(-1, -1), v(0, -1), v(0, 0), v(-1, 0)], axis=1)
        # as listed the quad's normal is +a: flip it where the solid lies on the +a side
        # (the lower corner is outside)
        q[~li] = q[~li][:, ::-1]
        quads.append(q)
    quads = np.concatenate(quads) if quads else np.zeros((0, 4), np.int64)
    if project_steps and len(verts):
        verts = project(ev, verts, steps=project_steps, max_step=h.max())[0]
        # the mean of a cell's crossings can lie in empty space or on the flat core of a
        # primitive (no gradient to follow) and stay off the surface: such a cell takes
        # one of its own (refined, on-surface) crossings instead
        fv, gv = ev.field_grad(verts)
        bad = ~on_surface(fv, iso, NEAR_SURFACE) | ~(np.einsum("ij,ij->i", gv, gv) > 0)
        if bad.any():
            verts[bad] = project(ev, cell_any[bad], steps=project_steps, max_step=h.max())[0]
    return Mesh(vertices=verts, quads=quads, cells=cells, grid=grid)


def thin_parts(ev, mesh, max_probes=200000):
    """Surface in cells the grid's sign changes miss: a part thinner than a cell (a
    wheel's disc between two grid planes) or a gap narrower than one. Along each grid
    edge whose ends are on the same side of iso, the field's cubic Hermite interpolant
    (from the ends' values and gradients) is checked for an interior peak (both ends
    outside) or dip (both inside); the field at that extremum is evaluated (one batch)
    and where it has the other sign, the edge's two crossings are refined. Returns
    (points on the surface, their cells)."""
    grid = mesh.grid
    f, iso, h, lo = grid.field, ev.iso, grid.cell, grid.lo
    inside = f >= iso
    # gradients at the corners of the support shell (outside with a field, or inside
    # near the surface): the only corners whose edges can hold an extremum
    need = (f > 0) & (f < 1.0) if iso < 1.0 else f > 0
    nidx = np.argwhere(need)
    G = np.zeros(f.shape + (3,))
    if len(nidx) == 0:
        return np.zeros((0, 3)), np.zeros((0, 3), np.int64)
    _, g = ev.field_grad(lo + nidx * h)
    G[tuple(nidx.T)] = g
    cand = []
    for a in range(3):
        sl0, sl1 = edge_ends(a)
        same = (inside[sl0] == inside[sl1]) & (need[sl0] | need[sl1])
        ijk = np.argwhere(same)
        if len(ijk) == 0:
            continue
        f0, f1 = f[sl0][same], f[sl1][same]
        s0, s1 = G[sl0][same][:, a] * h[a], G[sl1][same][:, a] * h[a]
        up = ~inside[sl0][same]                     # both outside: look for a peak
        # towards each other: rising into the edge from both ends (peak), falling (dip);
        # an end outside every support (no field, no gradient) counts as rising
        ok = np.where(up, (s0 >= 0) & (s1 <= 0), (s0 <= 0) & (s1 >= 0)) & ((s0 != 0) | (s1 != 0))
        ijk, f0, f1, s0, s1, up = ijk[ok], f0[ok], f1[ok], s0[ok], s1[ok], up[ok]
        # p(t) = A t^3 + B t^2 + s0 t + f0; p'(t) = 3A t^2 + 2B t + s0 = 0
        A = 2 * (f0 - f1) + s0 + s1
        B = 3 * (f1 - f0) - 2 * s0 - s1
        qa, qb, qc = 3 * A, 2 * B, s0
        disc = np.maximum(qb * qb - 4 * qa * qc, 0.0)
        sq = np.sqrt(disc)
        lin = np.abs(qa) < 1e-12
        with np.errstate(divide="ignore", invalid="ignore"):
            r1 = np.where(lin, -qc / np.where(qb == 0, 1.0, qb), (-qb + sq) / np.where(lin, 1.0, 2 * qa))
            r2 = np.where(lin, r1, (-qb - sq) / np.where(lin, 1.0, 2 * qa))
        best = np.full(len(ijk), 0.5)
        val = np.where(up, -np.inf, np.inf)
        for r in (r1, r2):
            r = np.where(np.isfinite(r), r, 0.5)
            inr = (r > 0) & (r < 1)
            p = ((A * r + B) * r + s0) * r + f0
            better = inr & np.where(up, p > val, p < val)
            best = np.where(better, r, best)
            val = np.where(better, p, val)
        cand.append((a, ijk, best, f0, f1))
    if not cand:
        return np.zeros((0, 3)), np.zeros((0, 3), np.int64)
    E0 = np.concatenate([lo + c[1] * h for c in cand])
    step = np.concatenate([np.tile(np.eye(3)[c[0]] * h, (len(c[1]), 1)) for c in cand])
    t, fe0, fe1 = (np.concatenate([c[k] for c in cand]) for k in (2, 3, 4))   # ends: the grid's values
    if len(E0) > max_probes:          # the most promising would need a score; keep a spread
        keep = np.linspace(0, len(E0) - 1, max_probes).astype(int)
        E0, step, t, fe0, fe1 = E0[keep], step[keep], t[keep], fe0[keep], fe1[keep]
    Pm = E0 + t[:, None] * step
    fm = ev.field(Pm)
    flip = (fm >= iso) != (fe0 >= iso)
    if not flip.any():
        return np.zeros((0, 3)), np.zeros((0, 3), np.int64)
    E0, E1, Pm, fm, fe0, fe1 = E0[flip], (E0 + step)[flip], Pm[flip], fm[flip], fe0[flip], fe1[flip]
    # both crossings of every edge (either side of its extremum) refined in one batch
    X = refine_crossings(ev, np.concatenate([E0, Pm]), np.concatenate([Pm, E1]), np.concatenate([fe0, fm]),
                         np.concatenate([fm, fe1]))
    X = project(ev, X, steps=6, max_step=h.max())[0]
    fx, gx = ev.field_grad(X)
    ok = on_surface(fx, iso) & (np.einsum("ij,ij->i", gx, gx) > 0)
    X = X[ok]
    cells = np.floor((X - lo) / h).astype(np.int64)
    inb = np.all((cells >= 0) & (cells < np.array(grid.res)), axis=1)
    X, cells = X[inb], cells[inb]
    return X, cells
