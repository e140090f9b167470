"""Silhouettes followed from the last frame's where only the eye moved (the field is the
same there): every point of a last frame's silhouette goes to this frame's by Newton's
method, all of them in one batch (Surface.silhouette_newton_steps, in the plane across
the outline through the old point), where tracing them again takes a sequential step
per point.

A followed point must pass the tests a trace step passes (converged, on the surface,
on the silhouette and on the sheet its old point was on: tracer.silhouette_kept) and
lie within REACH cells of where it was; two neighbours stay one outline where the
second lies ahead of the first along the old outline and at most tracer.FAR steps away.
Where neighbours are more than SPACING[1] steps apart, up to REFILL rounds of points are
put between them (the run is cut where they still are); then a point nearer its
predecessor than SPACING[0] steps is dropped (so neighbours end up at most SPACING[0]
+ SPACING[1] steps apart). The runs of followed points are kept as traced
(agents.continuation: they keep their order, so a stroke's start and direction stay
put), and a tracing task at each end of an open run traces on beyond it as the
outline's own (agents.traces.Traces.extend): where the outline grew (its cusp or the
crease it ends at moved) and across what could not be followed, up to the next run.
The old points of what was lost (with BESIDE followed ones to either side), and the
last ENDS points at either end of an open outline, seed the session as a moved
outline does (its brackets): a trace from a seed finds what the ends' tasks stop
short of.
"""
import numpy as np

from ..model.tolerances import on_surface
from .asks import run
from .outline import Outline
from .steering import unit
from .continuation import BRACKETS
from .tracer import FAR, silhouette_kept

REACH = BRACKETS[1]      # cells a followed point may move (as far as the seeds' widest bracket reaches)
SPACING = (0.5, 1.5)     # steps between neighbours of a followed outline, at least and at most
REFILL = 1               # rounds of points put between neighbours too far apart
SHORTEST = 3             # points of the shortest run kept (a shorter one is left to the tracer)
ENDS = 3                 # points at either end of an open outline left to seed the tracer
BESIDE = 2               # followed points to either side of a lost part that seed with it


def follow(surface, outlines, h, step_len, tol, crease_angle):
    """The last frame's silhouettes ``outlines`` (agents.outline.Outline) moved onto this
    frame's: (followed, lost), the runs followed (Outlines of this frame's points) and
    the parts of the old outlines that were not (Outlines of the old points, with
    BESIDE followed ones to either side: the seeds' outlines)."""
    outlines = [o for o in outlines if len(o.points) >= 2]
    if not outlines:
        return [], list(outlines)
    P = np.concatenate([o.points for o in outlines])
    T = np.concatenate([_tangents(o.points, o.closed) for o in outlines])
    steps = np.concatenate([np.full(len(o.points), o.step or step_len) for o in outlines])
    reach = REACH * h * steps / step_len
    N = np.concatenate([o.normals for o in outlines])
    X, n, good = _moved(surface, P, T, reach, tol, P, N, crease_angle)
    followed, lost = [], []
    start = 0
    for o in outlines:
        rows = slice(start, start + len(o.points))
        start += len(o.points)
        runs, gaps = _runs(X[rows], n[rows], T[rows], good[rows], o.closed, steps[rows][0])
        followed += [(o, r) for r in runs]
        lost += [_old_part(o, a, b) for a, b in gaps]
    followed, short = _spaced(surface, followed, step_len, h, tol, crease_angle)
    return followed, [o for o in lost + short if len(o.points) >= 2]


def _tangents(P, closed):
    if closed:
        return unit(np.roll(P, -1, axis=0) - np.roll(P, 1, axis=0))
    return unit(np.gradient(P, axis=0))


def _moved(surface, Q, T, reach, tol, back, n_back, crease_angle):
    """Points Q moved onto this frame's silhouette across their tangents T: the points,
    their normals and which are silhouette points within ``reach`` with no crease
    between them and ``back`` (points of the same sheet, normals ``n_back``: the
    normal at back predicted from the new point through the Hessian matches it, as a
    trace step's must)."""
    if len(Q) == 0:
        return np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0, bool)
    X, F, G, _, ok, bend = run(surface.ev, surface.silhouette_newton_steps(Q, T, reach, tol, back=back))[0]
    ok &= on_surface(F, surface.iso) & silhouette_kept(surface, X, G, bend, n_back, crease_angle)
    return X, surface.normals(G), ok


def _links(X, T, step):
    """Whether each point and the next are one outline: the next ahead, not far. (Each
    point stayed on its old point's sheet, :func:`_moved`: a link crosses no crease the
    old one did not.)"""
    d = X[1:] - X[:-1]
    ahead = np.einsum("ij,ij->i", d, T[:-1]) > 0
    near = np.linalg.norm(d, axis=1) <= FAR * step
    return ahead & near


def _runs(X, n, T, good, closed, step):
    """Runs (points, normals, tangents, closed) of followed points, and the (start, end)
    ranges of the old points not followed (a closed outline's may pass its last point)."""
    m = len(X)
    if not closed:                     # an open outline's last points seed the tracer too
        good = good.copy()
        good[:ENDS] = False
        good[m - ENDS:] = False
    wrap = (lambda a: np.vstack([a, a[:1]])) if closed else (lambda a: a)
    ok = _links(wrap(X), wrap(T), step)            # point i joins i + 1
    ok = np.append(ok, False)[:m] & good & np.roll(good, -1)
    if closed and ok.all():
        return [(X, n, T, True)], []
    # a closed outline's runs start just after a broken link
    order = np.roll(np.arange(m), -(int(np.flatnonzero(~ok)[0]) + 1)) if closed else np.arange(m)
    runs, lost, cur = [], [], []
    for i in order:
        if good[i]:
            cur.append(i)
        else:
            lost.append(i)
        if not ok[i]:                              # the run ends here
            if len(cur) >= SHORTEST:
                runs.append(cur)
            else:
                lost.extend(cur)
            cur = []
    return [(X[r], n[r], T[r], False) for r in runs], _ranges(sorted(lost), m, closed)


def _ranges(rows, m, closed):
    """Sorted rows as (start, end) ranges of consecutive rows, each grown by BESIDE to
    either side (a closed outline's ranges may wrap: end beyond m)."""
    if not rows:
        return []
    rows = np.asarray(rows)
    cut = np.flatnonzero(np.diff(rows) > 1) + 1
    out = [(int(r[0]) - BESIDE, int(r[-1]) + 1 + BESIDE) for r in np.split(rows, cut)]
    if closed and len(out) > 1 and out[0][0] <= 0 and out[-1][1] >= m:
        a, _ = out.pop()
        out[0] = (a, m + out[0][1])
    return [((a, b) if b - a <= m else (0, m)) if closed else (max(a, 0), min(b, m)) for a, b in out]


def _old_part(o, a, b):
    rows = np.arange(a, b) % len(o.points)
    return Outline(o.kind, o.points[rows], o.normals[rows], False, o.step)


def _spaced(surface, followed, step_len, h, tol, crease_angle):
    """Followed runs as Outlines with their neighbours SPACING apart: up to REFILL
    rounds of midpoints moved onto the silhouette where they are too far apart (the
    run is cut where they still are), then points too near their predecessor dropped;
    and the pieces left shorter than SHORTEST (as Outlines: seeds)."""
    runs = [[o, X, n, T, closed] for o, (X, n, T, closed) in followed]
    for round_ in range(REFILL + 1):
        far = [_far(X, closed, SPACING[1] * (o.step or step_len)) for o, X, _, _, closed in runs]
        if not any(len(f) for f in far):
            break
        if round_ == REFILL:
            runs = _cut(runs, far)
            break
        k = np.concatenate([np.full(len(f), j) for j, f in enumerate(far)])
        i = np.concatenate(far)
        Xi = np.concatenate([r[1][f] for f, r in zip(far, runs)])
        Xj = np.concatenate([r[1][(f + 1) % len(r[1])] for f, r in zip(far, runs)])
        ni = np.concatenate([r[2][f] for f, r in zip(far, runs)])
        Tq = unit(Xj - Xi)
        reach = np.array([REACH * h * (runs[a][0].step or step_len) / step_len for a in k])
        Xq, nq, good = _moved(surface, 0.5 * (Xi + Xj), Tq, reach, tol, Xi, ni, crease_angle)
        good &= (np.einsum("ij,ij->i", Xq - Xi, Tq) > 0) & (np.einsum("ij,ij->i", Xj - Xq, Tq) > 0)
        for a, r in enumerate(runs):
            m = (k == a) & good
            if m.any():
                at = i[m] + 1
                r[1], r[2], r[3] = (np.insert(r[1], at, Xq[m], axis=0), np.insert(r[2], at, nq[m], axis=0),
                                    np.insert(r[3], at, Tq[m], axis=0))
    out, short = [], []
    for o, X, n, _, closed in runs:
        keep = _thinned(X, SPACING[0] * (o.step or step_len), closed)
        (out if len(keep) >= SHORTEST else short).append(Outline(o.kind, X[keep], n[keep], closed, o.step))
    return out, short


def _far(X, closed, longest):
    """The links (their first points) longer than ``longest``."""
    d = np.linalg.norm((np.roll(X, -1, axis=0) - X) if closed else np.diff(X, axis=0), axis=1)
    return np.flatnonzero(d > longest)


def _thinned(X, shortest, closed):
    """Rows kept where each is at least ``shortest`` from the last kept (an open
    outline's last point kept; a closed one's last kept only that far from its first)."""
    d = np.linalg.norm((np.roll(X, -1, axis=0) - X) if closed else np.diff(X, axis=0), axis=1)
    if len(X) < 2 or (d >= shortest).all():
        return np.arange(len(X))
    keep = [0]
    for i in range(1, len(X)):
        if np.linalg.norm(X[i] - X[keep[-1]]) >= shortest or (i == len(X) - 1 and not closed):
            keep.append(i)
    while closed and len(keep) > 1 and np.linalg.norm(X[keep[-1]] - X[0]) < shortest:
        keep.pop()
    return np.array(keep)


def _cut(runs, far):
    """Runs cut at the links still too long (a closed run opens after the first)."""
    out = []
    for (o, X, n, T, closed), cuts in zip(runs, far):
        if not len(cuts):
            out.append([o, X, n, T, closed])
            continue
        cuts = list(cuts)
        if closed:                               # roll so the run starts after its first cut
            s = cuts[0] + 1
            X, n, T = (np.roll(a, -s, axis=0) for a in (X, n, T))
            cuts = sorted((c - s) % len(X) for c in cuts)
        prev = 0
        for c in cuts + ([] if closed else [len(X) - 1]):
            out.append([o, X[prev:c + 1], n[prev:c + 1], T[prev:c + 1], False])
            prev = c + 1
    return out
