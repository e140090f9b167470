"""Random numbers that belong to things rather than to a run: each value is a hash of a
key (a mark's, model.marks), a salt (what the value is for) and a counter, so it is the
same whatever else was drawn before it, in every frame and on every machine
(splitmix64's finaliser on uint64 arrays)."""
import numpy as np

_GOLDEN = np.uint64(0x9E3779B97F4A7C15)
_M1 = np.uint64(0xBF58476D1CE4E5B9)
_M2 = np.uint64(0x94D049BB133111EB)
_TO_UNIT = 1.0 / float(1 << 53)


def mix(x):
    """splitmix64's finaliser: a bijection of uint64 that scatters nearby inputs."""
    x = np.asarray(x, np.uint64)
    with np.errstate(over="ignore"):          # uint64 arithmetic wraps, as the hash wants
        x = (x ^ (x >> np.uint64(30))) * _M1
        x = (x ^ (x >> np.uint64(27))) * _M2
    return x ^ (x >> np.uint64(31))


def combine(keys, *values):
    """Keys mixed with more integers (a salt, a counter), each a scalar or per key."""
    h = np.asarray(keys, np.uint64)
    for v in values:
        with np.errstate(over="ignore"):
            h = mix(h + _GOLDEN + np.asarray(v).astype(np.uint64) * _GOLDEN)
    return h


def mark_keys(prim, index, salt=0):
    """The keys of marks: a primitive's number, the mark's index in its sequence, and
    the set's salt."""
    return combine(np.asarray(prim).astype(np.uint64), index, salt)


def uniform(keys, *salt, count=None):
    """Uniform numbers in [0, 1) for each key and salt (integers naming what they are
    for): (n,) or, with ``count``, (n, count)."""
    keys = np.asarray(keys, np.uint64)
    if count is None:
        return (combine(keys, *salt) >> np.uint64(11)).astype(np.float64) * _TO_UNIT
    cols = [combine(keys, *salt, c) for c in range(count)]
    return (np.stack(cols, axis=-1) >> np.uint64(11)).astype(np.float64) * _TO_UNIT


def normal(keys, *salt, count):
    """Standard normal numbers, (n, count) for each key and salt (Box-Muller)."""
    u = uniform(keys, *salt, count=2 * count)
    a, b = u[:, :count], u[:, count:]
    return np.sqrt(-2.0 * np.log1p(-a)) * np.cos(2.0 * np.pi * b)
