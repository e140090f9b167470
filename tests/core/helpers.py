"""Small helpers shared by core tests."""
import numpy as np


def near_surface_points(ev, n, seed=0, band=0.35):
    """Random points inside the support bounds whose field is within +-band of iso."""
    rng = np.random.default_rng(seed)
    lo, hi = ev.bounds
    out = []
    got = 0
    for _ in range(200):
        P = rng.uniform(lo, hi, size=(20000, 3))
        f = ev.field(P)
        keep = P[np.abs(f - ev.iso) < band]
        out.append(keep)
        got += len(keep)
        if got >= n:
            break
    return np.concatenate(out)[:n]


def fd_gradient(ev, P, h=1e-6):
    G = np.zeros_like(P)
    for k in range(3):
        e = np.zeros(3)
        e[k] = h
        G[:, k] = (ev.field(P + e) - ev.field(P - e)) / (2 * h)
    return G
