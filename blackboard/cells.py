"""Cells: integer cell (voxel) indices packed into one int64 key each, their
neighbourhoods, and points near points (pairs closer than a radius, found through a hash
of such cells, kept for many queries)."""
import numpy as np


_OFF = 1 << 20          # voxel indices from -2^20 to 2^20 - 1 pack into 21 bits each


def pack(ijk):
    ijk = np.asarray(ijk, np.int64) + _OFF
    if ijk.size and (ijk.min() < 0 or ijk.max() >= 2 * _OFF):
        raise ValueError("voxel index out of the blackboard's range (|i| < 2^20)")
    return (ijk[..., 0] << 42) | (ijk[..., 1] << 21) | ijk[..., 2]


_NEIGHBOURS = np.array([(dx, dy, dz) for dx in (-1, 0, 1) for dy in (-1, 0, 1) for dz in (-1, 0, 1)], np.int64)
_NEIGHBOUR_KEYS = (_NEIGHBOURS[:, 0] << 42) + (_NEIGHBOURS[:, 1] << 21) + _NEIGHBOURS[:, 2]


def pack_around(ijk):
    """(k, 27) packed keys of the 3x3x3 neighbourhood of each voxel (k, 3), in the
    order of _NEIGHBOURS: a voxel's key plus each offset's (packing is linear while
    every index stays in range, which the check of the voxels one step out ensures)."""
    ijk = np.asarray(ijk, np.int64).reshape(-1, 3)
    if ijk.size and (ijk.min() - 1 < -_OFF or ijk.max() + 1 >= _OFF):
        raise ValueError("voxel index out of the blackboard's range (|i| < 2^20)")
    return pack(ijk)[:, None] + _NEIGHBOUR_KEYS[None, :]


def unpack(keys):
    """The voxel triples (k, 3) of packed keys."""
    keys = np.asarray(keys, np.int64)
    mask = (1 << 21) - 1
    return np.stack([keys >> 42, (keys >> 21) & mask, keys & mask], axis=-1) - _OFF


def pairs_within(A, B, r):
    """Index pairs (i, j), i sorted, of the points A[i] and B[j] closer than r: B hashed
    in cells of at least r (the 27 cells around a point of A hold every B within r)."""
    return PointHash(B, r).pairs(A)


class PointHash:
    """Points B hashed once in cells of at least ``r``, for many :meth:`pairs` queries:
    a dense table of the cells' ranges where the cells over B's box are few (at most
    DENSE_CELLS, and DENSE_PER_POINT per point), else the packed keys, sorted."""

    def __init__(self, B, r):
        self.B = np.atleast_2d(np.asarray(B, float))
        self.r = float(r)
        self.order = None
        if len(self.B) == 0 or not self.r > 0:
            return
        self.lo = self.B.min(0)
        extent = float((self.B.max(0) - self.lo).max())
        self.cell = max(self.r, extent / (_OFF // 4))         # cell indices stay packable with room about them
        ijk = np.floor((self.B - self.lo) / self.cell).astype(np.int64)
        self.shape = ijk.max(0) + 3                            # a cell of room on either side
        if int(np.prod(self.shape)) <= min(DENSE_CELLS, DENSE_PER_POINT * len(self.B) + 4096):
            flat = self._flat(ijk + 1)
            self.order = np.argsort(flat, kind="stable")
            counts = np.bincount(flat, minlength=int(np.prod(self.shape)))
            self.first, self.counts = np.cumsum(counts) - counts, counts
            self.dense = True
        else:
            kb = pack(ijk)
            self.order = np.argsort(kb, kind="stable")
            self.kb = kb[self.order]
            self.dense = False

    def _flat(self, ijk):
        return (ijk[..., 0] * self.shape[1] + ijk[..., 1]) * self.shape[2] + ijk[..., 2]

    def pairs(self, A):
        """Index pairs (i, j), i sorted, of points A[i] and B[j] closer than r."""
        A = np.atleast_2d(np.asarray(A, float))
        none = np.zeros(0, np.int64)
        if self.order is None or len(A) == 0:
            return none, none
        ijk = np.floor((A - self.lo) / self.cell).astype(np.int64)
        if self.dense:
            inside = ((ijk >= -1) & (ijk <= self.shape - 3)).all(axis=1)     # else no B within r
            rows = np.flatnonzero(inside)
            around = self._flat((ijk[rows] + 1)[:, None, :] + _NEIGHBOURS[None, :, :]).ravel()
            start, count = self.first[around], self.counts[around]
            i = rows[np.repeat(np.arange(len(around)) // len(_NEIGHBOURS), count)]
        else:
            far = (np.abs(ijk) > _OFF // 2).any(axis=1)         # a point far outside the hashed box meets none
            if far.any():
                ijk[far] = -(_OFF // 2)
            ka = pack_around(ijk).ravel()
            start = np.searchsorted(self.kb, ka, "left")
            count = np.searchsorted(self.kb, ka, "right") - start
            i = np.repeat(np.arange(len(ka)) // len(_NEIGHBOURS), count)
        j = self.order[np.arange(int(count.sum())) - np.repeat(np.cumsum(count) - count - start, count)]
        near = ((A[i] - self.B[j]) ** 2).sum(-1) < self.r * self.r
        return i[near], j[near]


DENSE_CELLS = 1 << 21       # a PointHash keeps a dense table of its cells up to this many ...
DENSE_PER_POINT = 16        # ... and this many per point hashed (a table is filled at every hashing)
