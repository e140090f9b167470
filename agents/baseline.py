"""The papers' baseline (NPR-BlobTree): a Witkin-Heckbert particle system on the same
evaluator, for fair comparison with MASSRIS.

Particles start where random rays first meet the surface, then repel each other
(Gaussian energy, WH94) while an attraction term keeps them on the surface. Feature
outlines are found only where two neighbouring particles happen to straddle one (n.v
changes sign, or the normal jumps); each find is traced at once to completion, as
NPR-BT does, with the same tracer as MASSRIS.
"""
import time

import numpy as np
from numpy.random import default_rng    # numpy imports it lazily: here, not in a run's first call

from ..blackboard.board import FEATURE_KINDS, KIND_ID
from ..model import Evaluator
from ..model.tolerances import OUTLINE, on_surface
from .outline import Outline
from .stitch import stitch
from .surface import Surface
from .tracer import refine_seeds, trace_step


class Baseline:
    def __init__(self, model, view, particles=1000, seed=0, kinds=("silhouette", "crease"),
                 crease_angle=float(np.radians(35.0)), step=None):
        self.ev = model if isinstance(model, Evaluator) else Evaluator(model)
        self.view = view
        self.surface = Surface(self.ev, view)
        self.rng = default_rng(seed)
        self.kinds = kinds
        self.crease_angle = crease_angle
        t0 = time.perf_counter()
        self.P = self._random_rays(particles)
        lo, hi = self.ev.bounds
        area_guess = np.linalg.norm(hi - lo) ** 2
        self.sigma = 0.5 * np.sqrt(area_guess / max(len(self.P), 1))
        self.step_len = step if step is not None else 0.3 * self.sigma
        self.tol = OUTLINE * self.ev.scale
        self.iteration = 0
        self.deadline = None
        self.found = []
        self.traced_pts = {k: np.zeros((0, 3)) for k in range(len(FEATURE_KINDS))}
        self.rejected = {k: np.zeros((0, 3)) for k in range(len(FEATURE_KINDS))}   # false alarms
        self.init_seconds = time.perf_counter() - t0

    def _random_rays(self, n):
        lo, hi = self.ev.bounds
        c = 0.5 * (lo + hi)
        r = 0.5 * np.linalg.norm(hi - lo)
        hits = []
        tries = 0
        while sum(len(h) for h in hits) < n and tries < 50:
            tries += 1
            m = 4 * n
            d = self.rng.normal(size=(m, 3))
            d /= np.linalg.norm(d, axis=1, keepdims=True)
            O = c + r * d
            target = c + self.rng.uniform(-0.5, 0.5, size=(m, 3)) * (hi - lo)
            D = target - O
            D /= np.linalg.norm(D, axis=1, keepdims=True)
            ts = np.linspace(0, 2 * r, 200)
            t_hit = np.full(m, np.nan)
            for a, b in zip(ts[:-1], ts[1:]):
                live = np.isnan(t_hit)
                if not live.any():
                    break
                f = self.ev.field(O[live] + b * D[live])
                inside = f >= self.ev.iso
                idx = np.flatnonzero(live)[inside]
                t_hit[idx] = b
            ok = ~np.isnan(t_hit)
            P = O[ok] + t_hit[ok, None] * D[ok]
            P, f, g = self.surface.project(P)
            good = on_surface(f, self.ev.iso)
            hits.append(P[good])
        return np.concatenate(hits)[:n] if hits else np.zeros((0, 3))

    def step(self, budget=None):
        """One particle iteration: repel, re-attract, look for straddled outlines and
        trace each to completion (finds beyond the time budget wait for the next step)."""
        self.deadline = None if budget is None else time.perf_counter() + budget
        P = self.P
        if len(P) == 0:
            self.iteration += 1
            return True
        s2 = self.sigma ** 2
        diff = P[:, None, :] - P[None, :, :]
        d2 = np.einsum("ijk,ijk->ij", diff, diff)
        w = np.exp(-d2 / (2 * s2))
        np.fill_diagonal(w, 0.0)
        force = (w[:, :, None] * diff).sum(1)           # -grad of the WH energy, up to scale
        f, g = self.ev.field_grad(P)
        n = self.surface.normals(g)
        force -= np.einsum("ij,ij->i", force, n)[:, None] * n
        L = np.linalg.norm(force, axis=1, keepdims=True)
        move = force / np.maximum(L, 1e-300) * np.minimum(L, 0.5 * self.sigma)
        self.P, _, g = self.surface.project(P + 0.5 * move)
        self._find_and_trace(d2)
        self.iteration += 1
        return True

    def _find_and_trace(self, d2):
        P = self.P
        f, g = self.ev.field_grad(P)
        n = self.surface.normals(g)
        near = np.argwhere(np.triu(d2 < (2 * self.sigma) ** 2, 1))
        if len(near) == 0:
            return
        i, j = near[:, 0], near[:, 1]
        seeds = []
        if "silhouette" in self.kinds:
            s = np.einsum("ij,ij->i", n, self.view.towards_eye(P))
            m = (s[i] > 0) != (s[j] > 0)
            seeds += [(KIND_ID["silhouette"], a, b) for a, b in zip(i[m], j[m])]
        if "crease" in self.kinds:
            ang = np.arccos(np.clip(np.einsum("ij,ij->i", n[i], n[j]), -1, 1))
            m = ang > self.crease_angle
            seeds += [(KIND_ID["crease"], a, b) for a, b in zip(i[m], j[m])]
        for k, a, b in seeds:
            if self.deadline is not None and time.perf_counter() > self.deadline:
                break            # out of this step's time: the other finds wait for the next step
            mid = 0.5 * (P[a] + P[b])
            if self._near(k, mid, 1.5 * self.sigma):
                continue
            R = self.rejected[k]
            if len(R) and np.min(np.linalg.norm(R - mid, axis=1)) < 0.5 * self.sigma:
                continue
            self._trace(k, P[a], P[b])

    def _near(self, k, p, r):
        T = self.traced_pts[k]
        return len(T) > 0 and np.min(np.linalg.norm(T - p, axis=1)) < r

    def _trace(self, k, a, b):
        kinds = np.array([k])
        X, n, T, ref, A, B, valid, pins, _ = refine_seeds(self.surface, kinds, a[None], b[None], self.tol,
                                                          self.crease_angle)
        if not valid[0] or self._near(k, X[0], self.step_len):
            if not valid[0]:
                self.rejected[k] = np.vstack([self.rejected[k], 0.5 * (a + b)[None]])
            return
        pts, nrm = [X[0]], [n[0]]
        for direction in (1.0, -1.0):
            p, t, r, h = X[0], direction * T[0], ref[0], self.step_len
            pin, team = pins, (A, B)
            line, lnrm = [], []
            for _ in range(20000):
                if self.deadline is not None and time.perf_counter() > self.deadline:
                    break            # out of this step's time: keep what was traced
                st = trace_step(self.surface, kinds, p[None], t[None], r[None], np.array([h]), self.tol,
                                self.crease_angle, pins=pin, team=team)
                x, nn, tn, rn, ok = st.X, st.n, st.T, st.ref, st.ok
                if not ok[0]:
                    if h > self.step_len / 16:
                        h *= 0.5
                        continue
                    break
                h = min(self.step_len, 1.5 * h)
                if len(line) + len(pts) > 3 and np.linalg.norm(x[0] - X[0]) < 0.75 * self.step_len:
                    break
                if self._near(k, x[0], self.step_len):
                    break
                line.append(x[0])
                lnrm.append(nn[0])
                p, t, r = x[0], tn[0], rn[0]
                pin, team = st.pins, (st.A, st.B)
            if direction > 0:
                pts, nrm = pts + line, nrm + lnrm
            else:
                pts, nrm = line[::-1] + pts, lnrm[::-1] + nrm
        self.traced_pts[k] = np.vstack([self.traced_pts[k], np.array(pts)])
        self.found.append(Outline(FEATURE_KINDS[k], np.array(pts), np.array(nrm), False))

    def run(self, seconds=None, iterations=None):
        t0 = time.perf_counter()
        n = 0
        while (seconds is None or time.perf_counter() - t0 < seconds) and (iterations is None or n < iterations):
            self.step()
            n += 1
        return n

    def outlines(self):
        return stitch(self.found, 2.6 * self.step_len, Outline)
