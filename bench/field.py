"""Field evaluation speed: optimised (pruned, grouped) vs naive, side by side.

    python bench/field.py [--models heart,train,shell] [--points 100000]

For each model, on N points near the surface and on the corners of a 25^3 grid over
the model's bounds: field samples/s, field+gradient samples/s, primitives evaluated
per sample, and the speed-up over the naive evaluation (every node on every point),
each the best of a few repeats on one core.
"""
import argparse
import os
import sys
import time

os.environ.setdefault("OMP_NUM_THREADS", "1")
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools"))
import pure  # noqa: E402

pure.install()
import numpy as np  # noqa: E402
from blobtree_ink import model as M  # noqa: E402

EX = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "examples")


def near_surface(ev, n, seed=0):
    rng = np.random.default_rng(seed)
    lo, hi = ev.bounds
    out, got = [], 0
    while got < n:
        P = rng.uniform(lo, hi, size=(200_000, 3))
        f = ev.field(P)
        keep = P[np.abs(f - ev.iso) < 0.25]
        out.append(keep)
        got += len(keep)
    return np.concatenate(out)[:n]


def grid_corners(ev, res=25):
    lo, hi = ev.bounds
    ax = [np.linspace(lo[i], hi[i], res) for i in range(3)]
    X, Y, Z = np.meshgrid(*ax, indexing="ij")
    return np.stack([X.ravel(), Y.ravel(), Z.ravel()], axis=1)


def best_time(fn, repeats):
    best = np.inf
    for _ in range(repeats):
        t = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t)
    return best


def measure(ev, P, repeats):
    ev.stats = M.Stats()
    ev.field(P)
    per = ev.stats.primitives_per_point
    tf = best_time(lambda: ev.field(P), repeats)
    tg = best_time(lambda: ev.field_grad(P), repeats)
    return len(P) / tf, len(P) / tg, per


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--models", default="heart,train,shell")
    ap.add_argument("--points", type=int, default=100_000)
    ap.add_argument("--repeats", type=int, default=3)
    a = ap.parse_args()
    print(f"{'model':7} {'set':13} {'field/s':>11} {'f+grad/s':>11} {'prims/pt':>9} "
          f"{'naive f/s':>10} {'naive prims':>11} {'speed-up':>9}")
    for name in a.models.split(","):
        model = M.load(os.path.join(EX, f"{name}.json"))
        fast = M.Evaluator(model)
        naive = M.Evaluator(model, optimize=False)
        sets = {f"{a.points // 1000}k surface": near_surface(fast, a.points), "25^3 corners": grid_corners(fast)}
        for label, P in sets.items():
            f_rate, g_rate, per = measure(fast, P, a.repeats)
            nf_rate, _, nper = measure(naive, P, 1)
            print(f"{name:7} {label:13} {f_rate:11.3g} {g_rate:11.3g} {per:9.1f} "
                  f"{nf_rate:10.3g} {nper:11.0f} {f_rate / nf_rate:8.0f}x", flush=True)


if __name__ == "__main__":
    main()
