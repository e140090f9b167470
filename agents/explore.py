"""Exploration tasks (Table 1: find features in a region): an agent wanders on the
surface around a voxel (Reynolds wander in the tangent plane, with containment that
seeks the voxel's centre when it strays) and identifies feature points by comparing
each step with the previous one: a sign change of n.v (silhouette), of the mean
curvature, or a jump of the normal (crease). Found points go to the blackboard, where
the manager turns them into tracing tasks."""
import dataclasses

import numpy as np

from ..blackboard.board import FEATURE_KINDS, KIND_ID
from ..blackboard.keys import unique_rows
from ..blackboard.polygonise import thin_parts
from ..blackboard.subdivide import fine_features
from ..model.csg import subtracted_centres
from ..model.curvature import curvature
from ..model.tolerances import NEAR_SURFACE, on_surface
from ..strokes import steering as st
from .columns import Columns


def table():
    """An empty explorer table (agents.columns), one row per exploring agent: its agent,
    voxel and that voxel's centre (or its probe point), its position, heading and
    normal, its last n.v and mean curvature (compared with the next step's), and the
    steps it has taken."""
    v = ((3,), float)
    return Columns(agent=((), np.int64), voxel=((), np.int64), centre=v, p=v, d=v, n=v,
                   s_sil=((), float), s_curv=((), float), steps=((), np.int64))


def flagged_voxels(session):
    """Surface voxels whose corners say a feature may pass through them: the corner
    normals disagree on facing the eye (a silhouette) or diverge by more than the crease
    angle (a crease; theta_i of the manager). Polygon edges miss features smaller than
    a cell; these voxels are where agents look for them."""
    return session.bb.surface_rows[_flags(session)]


def _flags(session):
    s = session
    bb = s.bb
    rows = bb.surface_rows
    flag = np.zeros(len(rows), bool)
    if "silhouette" in s.settings.kinds and len(rows):
        P = bb.corner_pos.reshape(-1, 3)
        facing = np.einsum("ij,ij->i", bb.corner_normal.reshape(-1, 3), s.view.towards_eye(P))
        facing = facing.reshape(len(rows), 8)
        flag |= (facing > 0).any(axis=1) & (facing < 0).any(axis=1)
    if "crease" in s.settings.kinds:
        flag |= bb.vox["theta"][rows] > s.settings.crease_angle
    return flag


_PAIRS = np.array([(i, j) for i in range(8) for j in range(i + 1, 8)])


def corner_features(session, rows=None):
    """Identify feature points in the flagged voxels (of the surface voxel ``rows``, or
    all) where the polygon edges found none
    of that kind: the voxel's eight corners are projected onto the surface (one batch,
    each towards the projection of the voxel's centre where its own field is flat) and,
    of the 28 pairs of projected corners with a sign change of n.v (silhouette) or
    normals apart by more than the crease angle (crease), the closest pair (the most
    local bracket: corners may land on different parts) becomes an approximate feature
    point and its bracket. Sub-cell features (a vein's bump, a thin
    rim) show in the corners' normals though no polygon edge crosses them."""
    s = session
    bb = s.bb
    kinds = [k for k in ("silhouette", "crease") if k in s.settings.kinds]
    flag = _flags(s)
    if rows is not None:
        flag &= np.isin(bb.surface_rows, rows)
    if not kinds or not flag.any():
        return 0
    rows = bb.surface_rows[flag]
    C = bb.corner_pos[flag]                                            # (k, 8, 3)
    # neighbouring voxels share corners (about 3.5 voxel corners per grid corner): each
    # grid corner is projected once, towards the centre of the first voxel that has it
    # (projected in the same batch)
    key = np.round((C.reshape(-1, 3) - bb.lo) / bb.h).astype(np.int64)
    _, first, inv = unique_rows(key, return_index=True, return_inverse=True)
    k = len(C)
    P, f, g = s.surface.project(np.concatenate([C.mean(axis=1), C.reshape(-1, 3)[first]]),
                                anchor_rows=np.concatenate([np.full(k, -1), first // 8]))
    P, f, g = P[k:][inv.ravel()], f[k:][inv.ravel()], g[k:][inv.ravel()]
    on = (np.all(np.isfinite(P), axis=1) & on_surface(f, s.ev.iso, NEAR_SURFACE)).reshape(-1, 8)
    n = s.surface.normals(g).reshape(-1, 8, 3)
    P = P.reshape(-1, 8, 3)
    a, b = _PAIRS[:, 0], _PAIRS[:, 1]
    both = on[:, a] & on[:, b]
    near = 1.0 / (1e-300 + np.linalg.norm(P[:, a] - P[:, b], axis=2))     # (k, 28)
    added = 0
    for kind in kinds:
        if kind == "silhouette":
            sil = np.einsum("vck,vck->vc", n, s.view.towards_eye(P))
            pair = (sil[:, a] > 0) != (sil[:, b] > 0)
        else:
            ang = np.arccos(np.clip(np.einsum("vpk,vpk->vp", n[:, a], n[:, b]), -1, 1))
            pair = ang > s.settings.crease_angle
        score = np.where(both & pair, near, -1.0)
        have = bb.feat["voxel"][bb.feat["kind"] == KIND_ID[kind]]
        v = np.flatnonzero((score.max(axis=1) > 0) & ~np.isin(rows, have))
        if len(v) == 0:
            continue
        best = score[v].argmax(axis=1)
        A, B = P[v, a[best]], P[v, b[best]]
        bb.add_features(0.5 * (A + B), A, B, kind)
        added += len(v)
    return added


def missed_sheets(ev, mesh):
    """Sheets the rough polygonisation missed (parts thinner than a cell, found by
    probing the grid edges: polygonise.thin_parts): probe points in cells without a
    mesh vertex, or whose cell's vertex lies on another sheet (more than half a cell
    away, or its normal 60 degrees apart). Returns the mesh with the new cells' points
    as loose vertices (their voxels join the blackboard as surface voxels) and the
    points, where explorers start."""
    X, cells = thin_parts(ev, mesh)
    if len(X) == 0:
        return mesh, X
    h = float(mesh.grid.cell[0])
    vid = np.full(mesh.grid.res, -1, np.int64)
    if len(mesh.cells):
        vid[tuple(mesh.cells.T)] = np.arange(len(mesh.cells))
    own = vid[tuple(cells.T)]
    _, gx = ev.field_grad(X)
    missed = own < 0
    has = np.flatnonzero(~missed)
    if len(has):
        V = mesh.vertices[own[has]]
        _, gv = ev.field_grad(V)
        cos = np.einsum("ij,ij->i", gx[has], gv) / np.maximum(
            np.linalg.norm(gx[has], axis=1) * np.linalg.norm(gv, axis=1), 1e-300)
        missed[has] = (np.linalg.norm(X[has] - V, axis=1) > 0.5 * h) | (cos < 0.5)
    X, cells, own = X[missed], cells[missed], own[missed]
    new = np.flatnonzero(own < 0)
    if len(new):
        _, first = np.unique(np.ravel_multi_index(cells[new].T, mesh.grid.res), return_index=True)
        new = new[np.sort(first)]                     # one loose vertex per new cell
        mesh = dataclasses.replace(mesh, vertices=np.concatenate([mesh.vertices, X[new]]),
                                   cells=np.concatenate([mesh.cells, cells[new]]))
    return mesh, X


_AXES = np.concatenate([np.eye(3), -np.eye(3)])
_MARCH = np.linspace(0.0, 2.0, 17)
MAX_WALL_PROBES = 20000
MAX_SUBDIVIDED = 4000           # voxels subdivided around subtracted parts, at most


def subtracted_walls(session, model):
    """Points on the walls of the parts the model's differences cut away, where
    explorers start: from the centre of each subtracted primitive (model.csg), the
    first crossing of iso along each axis direction within two voxels (one batch),
    projected onto the surface. A wheel's holes are smaller than a cell of a rough grid;
    their creases start where these walls meet the faces they are cut from. Returns
    the points and, for each, the centre it was found from."""
    s = session
    C = subtracted_centres(model.root)
    if len(C) > MAX_WALL_PROBES:        # a spread subset: memory stays bounded (102 samples each)
        C = C[np.linspace(0, len(C) - 1, MAX_WALL_PROBES).astype(int)]
    none = (np.zeros((0, 3)), np.zeros((0, 3)))
    if len(C) == 0:
        return none
    R = C[:, None, None, :] + _AXES[None, :, None, :] * (_MARCH * s.h)[None, None, :, None]
    f = s.ev.field(R.reshape(-1, 3)).reshape(len(C), len(_AXES), len(_MARCH)) - s.ev.iso
    flip = (f[..., 1:] > 0) != (f[..., :1] > 0)
    ci, di = np.nonzero(flip.any(axis=-1))
    if len(ci) == 0:
        return none
    j = np.argmax(flip[ci, di], axis=-1)
    P, fp, _ = s.surface.project(R[ci, di, j + 1].copy(), anchor=R[ci, di, j])
    on = on_surface(fp, s.ev.iso)
    return P[on], C[ci[on]]


# voxels around a part's own: a cube of half-width 1.1 voxel (the largest reach) meets at most these
_BLOCK = np.array([(x, y, z) for x in range(-2, 3) for y in range(-2, 3) for z in range(-2, 3)], np.int64)


def subdivide(session, P, C):
    """Voxel subdivision (blackboard.subdivide) around the subtracted parts smaller than
    a cell (their walls P within a voxel of their centre C; the rough grid resolves
    larger ones, whose outlines traced at two scales would be drawn twice): each such
    part's voxels (those a cube around its centre as wide as its walls are far from it
    meets) are resampled on fine cells, and the feature points found there join the
    blackboard with the fine cells' size, so their agents trace at that scale. Returns
    how many were added."""
    s = session
    k = s.settings.subdivide
    kinds = [kind for kind in ("silhouette", "crease") if kind in s.settings.kinds]
    if len(P) == 0 or not k or not kinds:
        return 0
    centres, inv = np.unique(C, axis=0, return_inverse=True)
    reach = np.zeros(len(centres))
    np.maximum.at(reach, inv.reshape(-1), np.linalg.norm(P - C, axis=1))
    small = reach <= s.h
    centres, reach = centres[small], 1.1 * reach[small]
    lo, hi = s.bb.voxel_of(centres - reach[:, None]), s.bb.voxel_of(centres + reach[:, None])
    mid = s.bb.voxel_of(centres)
    cand = mid[:, None, :] + _BLOCK[None]                                   # (m, 125, 3)
    inside = np.all((cand >= lo[:, None]) & (cand <= hi[:, None]), axis=2)
    ijk = unique_rows(cand[inside])
    if len(ijk) > MAX_SUBDIVIDED:       # a spread subset: the fine sampling's cost stays bounded
        ijk = ijk[np.linspace(0, len(ijk) - 1, MAX_SUBDIVIDED).astype(int)]
    added = 0
    for kind, (pos, a, b) in fine_features(s.ev, s.bb.lo, s.h, ijk, k, s.view, s.settings.crease_angle,
                                           kinds).items():
        added += len(s.bb.add_features(pos, a, b, kind, s.h / k))
    return added


def queue_starts(session, P, region=None):
    """Queue explorers, ahead of the others, at the start points P (in the region, if
    one): one per voxel not explored or queued from a point yet."""
    s = session
    if region is not None and len(P):
        P = P[region.contains(P)]
    if len(P) == 0:
        return
    rows = []
    for row, p in zip(s.bb.voxel_rows(s.bb.voxel_of(P)), P):
        row = int(row)
        if row not in s.explored and row not in s.explore_from:
            s.explore_from[row] = p
            rows.append(row)
    s.explore_queue[:0] = rows[::-1]


def start(session, rows):
    """Send one free agent to each voxel row (as many rows as there are free agents are
    taken by the caller): all start positions projected in one batch."""
    s = session
    rows = [int(r) for r in rows]
    if not rows:
        return
    s.explored.update(rows)
    centres = s.bb.lo + (s.bb.vox["ijk"][rows] + 0.5) * s.h
    for i, r in enumerate(rows):
        if r in s.explore_from:            # a probe point on a sheet the polygonisation missed
            centres[i] = s.explore_from[r]
    P, f, g = s.surface.project(centres.copy())
    ok = np.all(np.isfinite(P), axis=1) & on_surface(f, s.ev.iso, NEAR_SURFACE)
    if not ok.any():
        return
    P, g, centres = P[ok], g[ok], centres[ok]
    rows = [r for r, k in zip(rows, ok) if k]
    n = s.surface.normals(g)
    d = st.unit(np.cross(n, s.rng.normal(size=(len(P), 3))))
    sil = np.einsum("ij,ij->i", n, s.view.towards_eye(P))
    curv = curvature(s.ev, P, g)["mean"]
    agents = [s.free.pop() for _ in rows]
    s.explorers.append(len(rows), agent=agents, voxel=rows, centre=centres, p=P, d=d, n=n, s_sil=sil, s_curv=curv,
                       steps=0)


def step(session):
    s = session
    ex = s.explorers
    if not ex:
        return []
    P, C, N = ex.p, ex.centre, ex.n
    # wander (the steering behaviour of the stroke smarticles); containment: seek the
    # voxel centre when further than a voxel from it
    D = st.wander(ex.d, N, s.rng, jitter=0.6)
    away = np.linalg.norm(P - C, axis=1) > s.h
    D[away] += 2.0 * np.linalg.norm(C[away] - P[away], axis=1)[:, None] / s.h * st.seek(P[away], C[away])
    D = st.unit(st.tangent(D, N))
    Q, f, g = s.surface.project(P + 0.35 * s.h * D)
    n = s.surface.normals(g)
    sil = np.einsum("ij,ij->i", n, s.view.towards_eye(Q))
    cq = curvature(s.ev, Q, g)
    curv = cq["mean"]
    rows = s.bb.add_samples(Q, f, g, "path", cq)
    # identify feature points: this step against the previous one
    kinds = set(s.settings.kinds)
    found = {}
    if "silhouette" in kinds:
        found["silhouette"] = (ex.s_sil > 0) != (sil > 0)
    if "curvature" in kinds:
        found["curvature"] = np.isfinite(curv) & ((ex.s_curv > 0) != (curv > 0))
    if "crease" in kinds:
        found["crease"] = np.arccos(np.clip(np.einsum("ij,ij->i", N, n), -1, 1)) > s.settings.crease_angle
    for kind in FEATURE_KINDS:
        if kind in found and found[kind].any():
            a, b = P[found[kind]], Q[found[kind]]
            s.bb.add_features(0.5 * (a + b), a, b, kind)
    ex.p, ex.d, ex.n, ex.s_sil, ex.s_curv = Q, D, n, sil, curv
    ex.steps += 1
    done = ex.steps >= s.settings.explore_steps
    s.free.extend(ex.agent[done].tolist())
    ex.keep(~done)
    return [rows]
