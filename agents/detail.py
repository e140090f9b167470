"""Features smaller than a blackboard cell (MASSRIS section 9), looked for before and
beside the polygon edges' seeds: the voxels whose corner normals disagree (flagged),
the closest pair of their projected corners with a sign change (corner features), the
sheets the rough polygonisation missed (parts thinner than a cell), the walls of the
parts a difference subtracts, and the voxels around the small ones resampled on fine
cells (voxel subdivision). Functions of the blackboard, the surface and the session's
settings they are given; found points join the blackboard as approximate features."""
import dataclasses

import numpy as np

from ..blackboard.board import KIND_ID
from ..blackboard.keys import unique_rows
from ..blackboard.polygonise import thin_parts
from ..blackboard.subdivide import fine_features
from ..model.csg import subtracted_centres
from ..model.tolerances import NEAR_SURFACE, on_surface


def flagged_voxels(board, surface, settings):
    """Surface voxels whose corners say a feature may pass through them: the corner
    normals disagree on facing the eye (a silhouette) or diverge by more than the crease
    angle (a crease; theta_i of the manager). Polygon edges miss features smaller than
    a cell; these voxels are where agents look for them."""
    return board.surface_rows[_flags(board, surface, settings)]


def _silhouette_flags(bb, surface):
    """Which surface voxels have corners that face the eye and corners that face away."""
    rows = bb.surface_rows
    if len(rows) == 0:
        return np.zeros(0, bool)
    P = bb.corner_pos.reshape(-1, 3)
    facing = np.einsum("ij,ij->i", bb.corner_normal.reshape(-1, 3), surface.view.towards_eye(P)).reshape(len(rows), 8)
    return (facing > 0).any(axis=1) & (facing < 0).any(axis=1)


def _flags(bb, surface, settings):
    rows = bb.surface_rows
    flag = np.zeros(len(rows), bool)
    if "silhouette" in settings.kinds and len(rows):
        flag |= _silhouette_flags(bb, surface)
    if "crease" in settings.kinds:
        flag |= bb.vox["theta"][rows] > settings.crease_angle
    return flag


_PAIRS = np.array([(i, j) for i in range(8) for j in range(i + 1, 8)])


def corner_features(bb, surface, settings, rows=None):
    """Identify feature points in the flagged voxels (of the surface voxel ``rows``, or
    all) where the polygon edges found none
    of that kind: the voxel's eight corners are projected onto the surface (one batch,
    each towards the projection of the voxel's centre where its own field is flat) and,
    of the 28 pairs of projected corners with a sign change of n.v (silhouette) or
    normals apart by more than the crease angle (crease), the closest pair (the most
    local bracket: corners may land on different parts) becomes an approximate feature
    point and its bracket. Sub-cell features (a vein's bump, a thin
    rim) show in the corners' normals though no polygon edge crosses them."""
    kinds = [k for k in ("silhouette", "crease") if k in settings.kinds]
    flag = _flags(bb, surface, settings)
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
    P, f, g = surface.project(np.concatenate([C.mean(axis=1), C.reshape(-1, 3)[first]]),
                                anchor_rows=np.concatenate([np.full(k, -1), first // 8]))
    P, f, g = P[k:][inv.ravel()], f[k:][inv.ravel()], g[k:][inv.ravel()]
    on = (np.all(np.isfinite(P), axis=1) & on_surface(f, surface.iso, NEAR_SURFACE)).reshape(-1, 8)
    n = surface.normals(g).reshape(-1, 8, 3)
    P = P.reshape(-1, 8, 3)
    a, b = _PAIRS[:, 0], _PAIRS[:, 1]
    both = on[:, a] & on[:, b]
    near = 1.0 / (1e-300 + np.linalg.norm(P[:, a] - P[:, b], axis=2))     # (k, 28)
    added = 0
    for kind in kinds:
        if kind == "silhouette":
            sil = np.einsum("vck,vck->vc", n, surface.view.towards_eye(P))
            pair = (sil[:, a] > 0) != (sil[:, b] > 0)
        else:
            ang = np.arccos(np.clip(np.einsum("vpk,vpk->vp", n[:, a], n[:, b]), -1, 1))
            pair = ang > settings.crease_angle
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
MAX_SUBDIVIDED = 4000           # voxels subdivided at once, at most
UNFOUND_SPREAD = np.radians(90.0)   # a voxel whose corner normals spread this far may hold a small silhouette


def subtracted_walls(surface, h, root):
    """Points on the walls of the parts the model's differences cut away, where
    explorers start: from the centre of each subtracted primitive (model.csg), the
    first crossing of iso along each axis direction within two voxels (one batch),
    projected onto the surface. A wheel's holes are smaller than a cell of a rough grid;
    their creases start where these walls meet the faces they are cut from. Returns
    the points and, for each, the centre it was found from."""
    C = subtracted_centres(root)
    if len(C) > MAX_WALL_PROBES:        # a spread subset: memory stays bounded (102 samples each)
        C = C[np.linspace(0, len(C) - 1, MAX_WALL_PROBES).astype(int)]
    none = (np.zeros((0, 3)), np.zeros((0, 3)))
    if len(C) == 0:
        return none
    R = C[:, None, None, :] + _AXES[None, :, None, :] * (_MARCH * h)[None, None, :, None]
    f = surface.ev.field(R.reshape(-1, 3)).reshape(len(C), len(_AXES), len(_MARCH)) - surface.iso
    flip = (f[..., 1:] > 0) != (f[..., :1] > 0)
    ci, di = np.nonzero(flip.any(axis=-1))
    if len(ci) == 0:
        return none
    j = np.argmax(flip[ci, di], axis=-1)
    P, fp, _ = surface.project(R[ci, di, j + 1].copy(), anchor=R[ci, di, j])
    on = on_surface(fp, surface.iso)
    return P[on], C[ci[on]]


# voxels around a part's own: a cube of half-width 1.1 voxel (the largest reach) meets at most these
_BLOCK = np.array([(x, y, z) for x in range(-2, 3) for y in range(-2, 3) for z in range(-2, 3)], np.int64)


def subdivide(bb, surface, settings, P, C):
    """Voxel subdivision (blackboard.subdivide) around the subtracted parts smaller than
    a cell (their walls P within a voxel of their centre C; the rough grid resolves
    larger ones, whose outlines traced at two scales would be drawn twice): each such
    part's voxels (those a cube around its centre as wide as its walls are far from it
    meets) are resampled on fine cells, and the feature points found there join the
    blackboard with the fine cells' size, so their agents trace at that scale. Returns
    how many were added."""
    k = settings.subdivide
    kinds = [kind for kind in ("silhouette", "crease") if kind in settings.kinds]
    if len(P) == 0 or not k or not kinds:
        return 0
    centres, inv = np.unique(C, axis=0, return_inverse=True)
    reach = np.zeros(len(centres))
    np.maximum.at(reach, inv.reshape(-1), np.linalg.norm(P - C, axis=1))
    small = reach <= bb.h
    centres, reach = centres[small], 1.1 * reach[small]
    lo, hi = bb.voxel_of(centres - reach[:, None]), bb.voxel_of(centres + reach[:, None])
    mid = bb.voxel_of(centres)
    cand = mid[:, None, :] + _BLOCK[None]                                   # (m, 125, 3)
    inside = np.all((cand >= lo[:, None]) & (cand <= hi[:, None]), axis=2)
    ijk = unique_rows(cand[inside])
    return _resample(bb, surface, settings, ijk)


def subdivide_at(bb, surface, settings, P, going_on=False):
    """Voxel subdivision where traces were lost (at points P), once the run has nothing
    else to do: a trace is lost where the outline does what its step cannot follow (a
    shell's apex, whose whorls and sutures are thinner than a voxel; a wheel seen edge
    on), and the rough grid may have found no feature point of what goes on there. The
    voxels of P not subdivided yet are resampled on fine cells; the feature points found
    join the blackboard at the fine cells' scale (those on outlines traced already are
    dropped when started). A frame ``going_on`` with the same model subdivides nothing:
    it follows the outlines the frames before it found, these included. Returns how
    many were added."""
    if len(P) == 0 or going_on:
        return 0
    return _resample(bb, surface, settings, bb.voxel_of(P))


def _at_most(a):
    """At most MAX_SUBDIVIDED of ``a``, spread over it: the fine sampling's cost stays bounded."""
    return a if len(a) <= MAX_SUBDIVIDED else a[np.linspace(0, len(a) - 1, MAX_SUBDIVIDED).astype(int)]


def _resample(bb, surface, settings, ijk):
    """Voxels ``ijk`` not subdivided yet resampled on fine cells (blackboard.subdivide;
    each voxel once): their feature points join the blackboard with the fine cells'
    size. Returns how many were added."""
    k = settings.subdivide
    kinds = [kind for kind in ("silhouette", "crease") if kind in settings.kinds]
    if not k or not kinds or len(ijk) == 0:
        return 0
    ijk = _at_most(unique_rows(np.asarray(ijk, np.int64).reshape(-1, 3)))
    ijk = bb.unsubdivided(ijk)
    added = 0
    for kind, (pos, a, b) in fine_features(surface.ev, bb.lo, bb.h, ijk, k, surface.view, settings.crease_angle,
                                           kinds).items():
        added += len(bb.add_features(pos, a, b, kind, bb.h / k))
    return added


def unfound_silhouettes(bb, surface, settings, outlines, wanted, swept=frozenset()):
    """Voxel subdivision where a silhouette may pass that no trace found, once the run has
    nothing else to do: surface voxels whose corners face the eye and away from it and
    whose corner normals spread more than UNFOUND_SPREAD (a thin part's tip or bead, as a
    vein's end, whose small closed silhouette no polygon edge crossed, no trace reached
    and so none lost), with no point of a traced silhouette or crease inside (a crease's
    faces spread as far: a crease traced there is why) and their centres
    ``wanted`` (a function of points: the session's requested regions), but those
    ``swept`` already (rows: the last frames', whose lines a frame going on follows).
    Unlike the lost traces' voxels these depend on the eye: a frame going on from the
    last, whose eye moved, looks where it brings new ones. Returns the rows looked in."""
    if "silhouette" not in settings.kinds or len(bb.surface_rows) == 0:
        return np.zeros(0, np.int64)
    rows = bb.surface_rows
    maybe = _silhouette_flags(bb, surface) & (bb.vox["theta"][rows] > UNFOUND_SPREAD)
    pts = [o.points for o in outlines if o.kind in ("silhouette", "crease") and len(o.points)]
    if pts:
        have = bb.voxel_rows(bb.voxel_of(np.concatenate(pts)), create=False)
        maybe &= ~np.isin(rows, have[have >= 0])
    if swept:
        maybe &= ~np.isin(rows, np.fromiter(swept, np.int64, len(swept)))
    look = rows[maybe]
    look = look[wanted(bb.lo + (bb.vox["ijk"][look] + 0.5) * bb.h)]
    look = _at_most(look)               # (as _resample takes them: the rows returned are those looked in)
    _resample(bb, surface, settings, bb.vox["ijk"][look])
    return look
