"""The blackboard: a voxel hash of surface voxels (and their neighbours) with the
samples agents and the polygonisation put there, per-voxel statistics, and feature
points (paper section 4).

Voxels are keyed by the integer triple (the voxel's back-bottom-left corner index),
packed into one int64 and kept in a sorted array beside the voxel rows, so lookups of
many voxels are one searchsorted, not a Python loop; voxel data and samples are rows
of growable arrays, so statistics are vector operations (bincount) too.
"""
import numpy as np

from .cells import _NEIGHBOURS, pack, pack_around, pairs_within, unpack
from .keys import unique_rows

from .polygonise import Mesh

SAMPLE_KINDS = {"corner": 0, "vertex": 1, "path": 2}
FEATURE_KINDS = ("silhouette", "crease", "curvature", "suggestive", "ridges")
VIEW_DEPENDENT = ("silhouette", "suggestive", "ridges")    # kinds that move with the eye (the others, with the field)
KIND_ID = {k: i for i, k in enumerate(FEATURE_KINDS)}


class Grow:
    """A set of growable column arrays sharing one row count."""

    def __init__(self, **cols):
        self.n = 0
        self.cols = {}
        for name, (shape, dtype, fill) in cols.items():
            self.cols[name] = np.full((16, *shape), fill, dtype)
        self.fill = {name: fill for name, (_, _, fill) in cols.items()}

    def add(self, count, **values):
        start = self.n
        end = start + count
        cap = len(next(iter(self.cols.values())))
        if end > cap:
            new = max(end, 2 * cap)
            for name, a in self.cols.items():
                b = np.full((new, *a.shape[1:]), self.fill[name], a.dtype)
                b[:cap] = a
                self.cols[name] = b
        for name, v in values.items():
            self.cols[name][start:end] = v
        self.n = end
        return np.arange(start, end)

    def __getitem__(self, name):
        return self.cols[name][:self.n]

    def __len__(self):
        return self.n


_CORNERS = np.array([(x, y, z) for x in (0, 1) for y in (0, 1) for z in (0, 1)], np.int64)
_CORNER_PAIRS = np.triu_indices(8, 1)


def _unique_ijk(ijk):
    """Distinct voxel triples, in packed-key order."""
    return unpack(np.unique(pack(np.asarray(ijk, np.int64).reshape(-1, 3))))


class VoxelIndex:
    """Voxel keys -> rows: a sorted key array and the rows in the same order, and a
    dense array of rows over a box of voxels (the grid's, with a margin: where the
    polygonisation's voxels and their neighbours lie) for the neighbourhoods of many
    voxels at once."""

    def __init__(self, lo=(0, 0, 0), shape=(0, 0, 0)):
        self.keys = np.zeros(0, np.int64)
        self.rows = np.zeros(0, np.int64)
        self.lo = np.asarray(lo, np.int64)
        self.shape = np.asarray(shape, np.int64)
        self.dense = np.full(int(np.prod(self.shape)), -1, np.int64)
        self.strides = np.array([self.shape[1] * self.shape[2], self.shape[2], 1], np.int64)
        self.offsets = _NEIGHBOURS @ self.strides            # of the 27 neighbours in the box

    def __len__(self):
        return len(self.keys)

    def lookup(self, keys):
        keys = np.asarray(keys, np.int64)
        if len(self.keys) == 0:
            return np.full(keys.shape, -1, np.int64)
        i = np.minimum(np.searchsorted(self.keys, keys), len(self.keys) - 1)
        return np.where(self.keys[i] == keys, self.rows[i], -1)

    def _in_box(self, ijk, margin):
        return np.all((ijk - margin >= self.lo) & (ijk + margin < self.lo + self.shape), axis=1)

    def insert(self, keys, rows, ijk):
        keys = np.concatenate([self.keys, np.asarray(keys, np.int64)])
        rows_all = np.concatenate([self.rows, np.asarray(rows, np.int64)])
        order = np.argsort(keys, kind="stable")
        self.keys, self.rows = keys[order], rows_all[order]
        inside = self._in_box(ijk, 0)
        self.dense[(ijk[inside] - self.lo) @ self.strides] = np.asarray(rows, np.int64)[inside]

    def around(self, ijk):
        """(k, 27) rows of the 3x3x3 neighbourhood of each voxel (k, 3), -1 where absent
        (the dense box where the whole neighbourhood lies in it, else the keys)."""
        inside = self._in_box(ijk, 1)
        out = np.empty((len(ijk), len(_NEIGHBOURS)), np.int64)
        out[inside] = self.dense.take(((ijk[inside] - self.lo) @ self.strides)[:, None] + self.offsets[None, :])
        if not inside.all():
            out[~inside] = self.lookup(pack_around(ijk[~inside]))
        return out


class Blackboard:
    def __init__(self, grid, iso):
        self.grid = grid
        self.iso = iso
        self.h = float(grid.cell[0])
        self.lo = grid.lo.copy()
        self.index = VoxelIndex(-2, np.asarray(grid.res) + 4)   # (i, j, k) -> voxel row
        self.vox = Grow(ijk=((3,), np.int64, 0), corners_in=((), np.int8, 0), theta=((), float, 0.0),
                        surface=((), bool, False), features=((), np.int64, 0), samples=((), np.int64, 0),
                        sum=((), float, 0.0), sumsq=((), float, 0.0), fmin=((), float, np.inf),
                        fmax=((), float, -np.inf), path_steps=((), np.int64, 0), subdivided=((), bool, False),
                        nbr=((len(_NEIGHBOURS),), np.int32, -1))
        self.smp = Grow(pos=((3,), float, 0.0), f=((), float, 0.0), grad=((3,), float, 0.0),
                        mean=((), float, np.nan), gauss=((), float, np.nan), dir1=((3,), float, 0.0),
                        voxel=((), np.int64, -1), kind=((), np.int8, 0))
        self.feat = Grow(pos=((3,), float, 0.0), a=((3,), float, 0.0), b=((3,), float, 0.0),
                         kind=((), np.int8, 0), voxel=((), np.int64, -1), used=((), bool, False),
                         cell=((), float, 0.0), rounds=((), np.int64, 0))
        self.surface_rows = np.zeros(0, np.int64)       # surface voxels, in the order they came
        self.corner_pos = np.zeros((0, 8, 3))            # ... their corners
        self.corner_normal = np.zeros((0, 8, 3))         # ... and the outward normals there (0: none)

    # --- voxels ---------------------------------------------------------------------
    def voxel_of(self, P):
        return np.floor((np.asarray(P, float) - self.lo) / self.h).astype(np.int64)

    def voxel_rows(self, ijk, create=True):
        """Rows of voxels (k,3) int; missing ones are added when create (else -1), in
        the order they first appear."""
        ijk = np.atleast_2d(np.asarray(ijk, np.int64))
        keys = pack(ijk)
        rows = self.index.lookup(keys)
        miss = rows < 0
        if create and miss.any():
            new, first, inv = np.unique(keys[miss], return_index=True, return_inverse=True)
            order = np.argsort(first, kind="stable")          # rows in order of first appearance
            rank = np.empty(len(new), np.int64)
            rank[order] = np.arange(len(new))
            new_rows = self.vox.n + rank
            self.index.insert(new, new_rows, ijk[miss][first])
            rows[miss] = new_rows[inv.reshape(-1)]
            self.vox.add(len(new), ijk=ijk[miss][first[order]])
            added = np.arange(self.vox.n - len(new), self.vox.n)
            self._corner_info(added)
            self._link(added)
        return rows

    def unsubdivided(self, ijk):
        """Of voxels ``ijk``, those not subdivided yet (each once), now marked
        subdivided (blackboard.subdivide resamples them)."""
        ijk = unique_rows(np.atleast_2d(np.asarray(ijk, np.int64)))
        rows = self.voxel_rows(ijk)
        new = ~self.vox.cols["subdivided"][rows]
        self.vox.cols["subdivided"][rows[new]] = True
        return ijk[new]

    def _corner_info(self, rows):
        """Corner counts and the max angle between corner gradients (from the grid)."""
        g = self.grid
        f = g.field
        ijk = self.vox["ijk"][rows]
        res = np.array(g.res)
        inside_grid = np.all((ijk >= 0) & (ijk < res), axis=1)
        cnt = np.zeros(len(rows), np.int8)
        for dx in (0, 1):
            for dy in (0, 1):
                for dz in (0, 1):
                    c = ijk + (dx, dy, dz)
                    ok = inside_grid
                    vals = np.zeros(len(rows))
                    vals[ok] = f[c[ok, 0], c[ok, 1], c[ok, 2]]
                    cnt += (vals >= self.iso).astype(np.int8)
        self.vox.cols["corners_in"][rows] = cnt

    def set_theta(self, rows, theta):
        self.vox.cols["theta"][rows] = theta

    def _link(self, rows):
        """Fill the neighbour rows of new voxels (rows: the last ones, in order), and
        theirs in the older voxels around them (offset k seen from the other side is
        offset 26 - k)."""
        nb = self.index.around(self.vox["ijk"][rows])
        table = self.vox.cols["nbr"]
        table[rows] = nb
        r, k = np.nonzero((nb >= 0) & (nb < rows[0]))         # the voxels there before
        table[nb[r, k], len(_NEIGHBOURS) - 1 - k] = rows[r]

    def neighbours(self, rows):
        """(k, 27) rows of the 3x3x3 neighbourhood of each voxel (-1 where absent)."""
        return self.vox["nbr"][np.asarray(rows, np.int64)]

    def add_surface(self, cells, vertices, ev, curvature_fn):
        """Surface voxels (cells: grid cells (k, 3), none of them in ``surface_rows`` yet) with
        a vertex on the surface in each: the voxels and their 26 neighbours join the
        board, the cells' corner gradients give theta_i (the largest angle between two
        of them) and corner samples, and the vertices are sampled with their curvature.
        The polygonisation's cells come in at initialisation; sheets it missed, when
        agents find them. Returns the surface voxels' rows and the vertices' curvature."""
        cells = np.asarray(cells, np.int64).reshape(-1, 3)
        around = unpack(np.unique(pack_around(cells)))     # as _unique_ijk, from the neighbours' keys
        self.voxel_rows(around)
        srows = self.voxel_rows(cells)
        self.vox.cols["surface"][srows] = True
        # corner gradients of surface voxels: the max angle between them (theta_i)
        corners = (cells[:, None, :] + _CORNERS[None]).reshape(-1, 3)
        corner_ijk = _unique_ijk(corners)
        cpos = self.grid.lo + corner_ijk * self.grid.cell
        cf, cg = ev.field_grad(cpos)
        unit = cg / np.maximum(np.linalg.norm(cg, axis=1, keepdims=True), 1e-300)
        zero = np.linalg.norm(cg, axis=1) == 0
        idx = np.searchsorted(pack(corner_ijk), pack(corners)).reshape(-1, 8)    # corner_ijk is sorted by key
        # the 28 pairs of each voxel's corners at once; a pair with a zero gradient counts
        # as angle 0, and the largest angle is that of the smallest cosine
        a, b = _CORNER_PAIRS
        U, z = unit.take(idx, axis=0), zero.take(idx)       # take: fancy indexing is several times slower
        dot = np.clip(np.einsum("kpd,kpd->kp", U.take(a, axis=1), U.take(b, axis=1)), -1, 1)
        theta = np.arccos(np.where(z[:, a] | z[:, b], 1.0, dot).min(axis=1, initial=1.0))
        self.set_theta(srows, theta)
        # kept per surface voxel for the view-dependent flags of the manager's explorers
        self.surface_rows = np.concatenate([self.surface_rows, srows])
        self.corner_pos = np.concatenate([self.corner_pos, cpos.take(idx, axis=0)])                # (k, 8, 3)
        self.corner_normal = np.concatenate([self.corner_normal, np.where(z[..., None], 0.0, -U)])  # outward, 0: none
        self.add_samples(cpos, cf, cg, "corner")
        vf, vg = ev.field_grad(vertices)
        curv = curvature_fn(vertices, vg)
        self.add_samples(vertices, vf, vg, "vertex", curv)
        return srows, curv

    # --- samples --------------------------------------------------------------------
    def add_samples(self, pos, f, grad, kind, curv=None):
        pos = np.atleast_2d(pos)
        rows = self.voxel_rows(self.voxel_of(pos))
        vals = dict(pos=pos, f=f, grad=grad, voxel=rows, kind=SAMPLE_KINDS[kind])
        if curv is not None:
            vals.update(mean=curv["mean"], gauss=curv["gauss"], dir1=curv["dir1"])
        self.smp.add(len(pos), **vals)
        v = self.vox.cols
        np.add.at(v["samples"], rows, 1)
        np.add.at(v["sum"], rows, f)
        np.add.at(v["sumsq"], rows, f * f)
        np.minimum.at(v["fmin"], rows, f)
        np.maximum.at(v["fmax"], rows, f)
        on = np.abs(np.asarray(f) - self.iso) < 1e-3
        v["surface"][rows[on]] = True
        if kind == "path":
            np.add.at(v["path_steps"], rows, 1)
        return rows

    def stats(self, rows=None):
        """Per-voxel sample statistics: count, average, range, standard deviation."""
        v = self.vox
        rows = np.arange(v.n) if rows is None else rows
        n = v["samples"][rows].astype(float)
        safe = np.maximum(n, 1)
        avg = v["sum"][rows] / safe
        var = np.maximum(v["sumsq"][rows] / safe - avg * avg, 0.0)
        rng = np.where(n > 0, v["fmax"][rows] - v["fmin"][rows], 0.0)
        return {"count": n, "average": np.where(n > 0, avg, np.nan), "range": rng,
                "std": np.where(n > 0, np.sqrt(var), np.nan)}

    # --- feature points -------------------------------------------------------------
    def add_features(self, pos, a, b, kind, cell=None, rounds=0):
        """Approximate feature points with their brackets (a, b); ``cell``: the size of
        the grid cells that found them (default the blackboard's voxel; smaller for a
        subdivided voxel's), the scale at which agents trace from them. ``rounds``
        above 0: feature points already counted, whose brackets an agent narrowed
        that many times without settling them (they go on from there)."""
        pos = np.atleast_2d(pos)
        if len(pos) == 0:
            return np.zeros(0, np.int64)
        rows = self.voxel_rows(self.voxel_of(pos))
        ids = self.feat.add(len(pos), pos=pos, a=a, b=b, kind=KIND_ID[kind], voxel=rows,
                            cell=self.h if cell is None else cell, rounds=rounds)
        again = np.broadcast_to(rounds, (len(pos),)) > 0
        np.add.at(self.vox.cols["features"], rows[~again], 1)
        return ids

    def open_features(self, kind=None):
        ok = ~self.feat["used"]
        if kind is not None:
            ok &= self.feat["kind"] == KIND_ID[kind]
        return np.flatnonzero(ok)

    def open_near(self, P, kind, radius):
        """Open feature points of this kind within radius of any of P: their ids and,
        for each, the index of its nearest point of P."""
        ids = self.open_features(kind)
        P = np.atleast_2d(P)
        if len(ids) == 0 or len(P) == 0:
            return np.zeros(0, np.int64), np.zeros(0, np.int64)
        fp = self.feat["pos"][ids]
        i, j = pairs_within(fp, P, radius)
        d2 = ((fp[i] - P[j]) ** 2).sum(-1)
        order = np.lexsort((j, d2, i))          # each feature's nearest point, the first on ties
        i, j = i[order], j[order]
        first = np.ones(len(i), bool)
        np.not_equal(i[1:], i[:-1], out=first[1:])
        return ids[i[first]], j[first]

    def consume(self, ids):
        """Mark feature points as used (taken, or covered by a traced outline)."""
        self.feat.cols["used"][ids] = True


def from_mesh(mesh: Mesh, ev, curvature_fn):
    """A blackboard initialised from the rough polygonisation: surface voxels and their
    neighbours, corner samples of surface voxels, and vertex samples with curvature.
    Returns it and the vertices' curvature (``curvature_fn(P, grad)``)."""
    bb = Blackboard(mesh.grid, ev.iso)
    _, curv = bb.add_surface(mesh.cells, mesh.vertices, ev, curvature_fn)
    return bb, curv
