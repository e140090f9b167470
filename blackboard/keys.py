"""Unique rows of small integer arrays (voxel and cell indices, mesh edges) by one
int64 key per row.

``np.unique(a, axis=0)`` sorts the rows as structured records, several times slower
than sorting one integer per row. The rows are encoded in mixed radix, the first
column most significant, so that the keys sort as the rows do lexicographically: the
results (unique rows, first indices, inverse) are exactly ``np.unique``'s.
"""
import numpy as np

_KEY_LIMIT = 2**62


def unique_rows(a, return_index=False, return_inverse=False):
    """``np.unique(a, axis=0, ...)`` for an integer (n, d) array; the inverse is 1-D."""
    a = np.asarray(a)
    if a.ndim != 2 or a.dtype.kind not in "iu":
        raise ValueError(f"unique_rows takes an (n, d) integer array, got {a.dtype} of shape {a.shape}")
    if len(a) == 0 or a.shape[1] == 0:
        out = np.unique(a, axis=0, return_index=return_index, return_inverse=return_inverse)
        return _ravel_inverse(out, return_index, return_inverse)
    lo = a.min(axis=0).astype(np.int64)
    span = a.max(axis=0).astype(np.int64) - lo + 1
    radix = np.ones(a.shape[1], np.int64)
    total = 1
    for j in range(a.shape[1] - 1, -1, -1):
        radix[j] = total
        total *= int(span[j])
    if total >= _KEY_LIMIT:          # too wide for one int64 key: numpy's row sort
        out = np.unique(a, axis=0, return_index=return_index, return_inverse=return_inverse)
        return _ravel_inverse(out, return_index, return_inverse)
    key = (a.astype(np.int64) - lo) @ radix
    out = np.unique(key, return_index=return_index, return_inverse=return_inverse)
    keys = out[0] if isinstance(out, tuple) else out
    rows = np.empty((len(keys), a.shape[1]), a.dtype)
    rest = keys
    for j in range(a.shape[1]):
        rows[:, j] = rest // radix[j] + lo[j]
        rest = rest % radix[j]
    if not isinstance(out, tuple):
        return rows
    return _ravel_inverse((rows,) + tuple(out[1:]), return_index, return_inverse)


def _ravel_inverse(out, return_index, return_inverse):
    if not isinstance(out, tuple):
        return out
    if return_inverse:
        out = out[:-1] + (np.asarray(out[-1]).ravel(),)
    return out
