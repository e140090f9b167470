"""MASSRIS on analytic models: silhouettes and creases against their exact curves,
the manager's priorities against hand-computed equations 1-3, determinism."""
import math

import numpy as np
import pytest

from blobtree_ink import model as M
from blobtree_ink.agents import Region, Session, Settings
from blobtree_ink.agents import manager
from blobtree_ink.blackboard.board import KIND_ID, Blackboard
from blobtree_ink.blackboard.polygonise import Grid
from blobtree_ink.blackboard.view import View

K = math.sqrt(1 - 0.5 ** (1 / 3))


def model_of(root):
    return M.from_dict({"format": "blobtree-1", "root": root})


def run(model, view, **kw):
    s = Session(model, view, Settings(**kw))
    s.request("OUTLINES")
    s.run()
    assert s.done
    return s


def check_on_surface(s, outline):
    f, g = s.ev.field_grad(outline.points)
    dist = np.abs(f - s.ev.iso) / np.linalg.norm(g, axis=1)
    assert dist.max() < 1e-6 * s.ev.scale
    np.testing.assert_allclose(np.linalg.norm(outline.normals, axis=1), 1, atol=1e-9)


def coverage(points, curve, radius):
    d = np.linalg.norm(curve[:, None, :] - points[None, :, :], axis=2).min(axis=1)
    return d.max(), np.mean(d < radius)


def circle(centre, axis, radius, n=720):
    axis = axis / np.linalg.norm(axis)
    u = np.cross(axis, [1, 0, 0] if abs(axis[0]) < 0.9 else [0, 1, 0])
    u /= np.linalg.norm(u)
    w = np.cross(axis, u)
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    return centre + radius * (np.cos(t)[:, None] * u + np.sin(t)[:, None] * w)


def polyline_samples(outline, per=8):
    P = np.vstack([outline.points, outline.points[:1]]) if outline.closed else outline.points
    t = np.linspace(0, 1, per, endpoint=False)
    return np.concatenate([P[:-1] + tt * (P[1:] - P[:-1]) for tt in t] + [P[-1:]])


@pytest.mark.parametrize("view", [View(eye=(6, -9, 5)), View(eye=(0.5, 0.3, 4)), View(direction=(1, 1, -1)),
                                  View(direction=(0, 0, 1))])
def test_sphere_silhouette_is_the_expected_circle(view):
    C, R = np.array([0.3, -0.2, 0.1]), 1.5
    r = K * R
    s = run(model_of({"type": "point", "center": list(C), "radius": R}), view, resolution=16)
    sil = [o for o in s.outlines() if o.kind == "silhouette"]
    assert len(sil) == 1 and not [o for o in s.outlines() if o.kind != "silhouette"]
    o = sil[0]
    check_on_surface(s, o)
    nv = np.einsum("ij,ij->i", o.normals, view.towards_eye(o.points))
    assert np.abs(nv).max() < 1e-3
    if view.eye is not None:
        d = np.linalg.norm(view.eye - C)
        axis = (view.eye - C) / d
        ref = circle(C + r * r / d * axis, axis, r * math.sqrt(1 - r * r / (d * d)))
    else:
        ref = circle(C, view.direction, r)
    worst, covered = coverage(polyline_samples(o), ref, 0.01 * r)
    assert covered == 1.0, (worst, covered)
    assert abs(o.length - np.linalg.norm(np.diff(np.vstack([ref, ref[:1]]), axis=0), axis=1).sum()) < 0.02 * r


def two_sphere_crease(c0, r0, c1, r1):
    d = np.linalg.norm(c1 - c0)
    a = (d * d + r0 * r0 - r1 * r1) / (2 * d)
    axis = (c1 - c0) / d
    return c0 + a * axis, axis, math.sqrt(r0 * r0 - a * a)


@pytest.mark.parametrize("op", ["difference", "union"])
def test_csg_crease_is_the_analytic_circle(op):
    c0, c1 = np.array([0.0, 0, 0]), np.array([0.6, 0.1, -0.1])
    R0, R1 = 1.5, 1.2
    root = {"type": op, "children": [{"type": "point", "center": list(c0), "radius": R0},
                                     {"type": "point", "center": list(c1), "radius": R1}]}
    s = run(model_of(root), View(eye=(4, -6, 3)), resolution=20)
    creases = [o for o in s.outlines() if o.kind == "crease"]
    assert creases
    centre, axis, rad = two_sphere_crease(c0, K * R0, c1, K * R1)
    pts = np.concatenate([o.points for o in creases])
    for o in creases:
        check_on_surface(s, o)
    # every traced point on the analytic circle
    rel = pts - centre
    along = rel @ axis
    radial = np.linalg.norm(rel - along[:, None] * axis, axis=1)
    assert np.abs(along).max() < 1e-6 and np.abs(radial - rad).max() < 1e-6
    # and the whole circle covered
    samples = np.concatenate([polyline_samples(o) for o in creases])
    worst, covered = coverage(samples, circle(centre, axis, rad), 0.02 * rad)
    assert covered == 1.0, (worst, covered)


def test_torus_at_an_angle_yields_all_silhouette_components():
    a, R = 1.0, 0.8
    b = K * R
    view = View(direction=(0.0, -math.cos(0.6), -math.sin(0.6)))     # looking down at 34 degrees
    s = run(model_of({"type": "circle", "center": [0, 0, 0], "normal": [0, 0, 1], "circle_radius": a,
                      "radius": R}), view, resolution=24)
    sil = [o for o in s.outlines() if o.kind == "silhouette"]
    for o in sil:
        check_on_surface(s, o)
        assert np.abs(np.einsum("ij,ij->i", o.normals, view.towards_eye(o.points))).max() < 1e-3
    # exact silhouette of the torus: points (u, v) with n.d = 0, found densely
    u = np.linspace(0, 2 * np.pi, 1440, endpoint=False)
    d = -view.direction
    ref = []
    for uu in u:
        # n(u, v) = (cos v cos u, cos v sin u, sin v): n.d = 0 -> v from atan
        A = math.cos(uu) * d[0] + math.sin(uu) * d[1]
        for v in (math.atan2(-A, d[2]), math.atan2(A, -d[2])):
            ref.append(((a + b * math.cos(v)) * math.cos(uu), (a + b * math.cos(v)) * math.sin(uu),
                        b * math.sin(v)))
    ref = np.array(ref)
    samples = np.concatenate([polyline_samples(o) for o in sil])
    worst, covered = coverage(samples, ref, 0.05 * b)
    assert covered > 0.99, (worst, covered)
    assert len(sil) >= 2          # the outer and the inner loop at least


def test_priorities_reproduce_equations_1_to_3():
    # a 3x1x1 blackboard: voxel 0 (3 corners in, theta 0.2), 1 (4 in, theta 0.8), 2 (1 in, theta 0.4)
    f = np.zeros((4, 2, 2))
    grid = Grid(lo=np.zeros(3), cell=np.ones(3), res=(3, 1, 1), field=f)
    bb = Blackboard(grid, 0.5)
    rows = bb.voxel_rows(np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0]]))
    bb.vox.cols["corners_in"][rows] = [3, 4, 1]
    bb.vox.cols["theta"][rows] = [0.2, 0.8, 0.4]
    bb.vox.cols["samples"][rows] = [10, 5, 0]
    bb.vox.cols["features"][rows] = [1, 0, 3]
    lod = 0.5
    got = manager.priorities(bb, rows, lod)
    # by hand: every voxel's neighbourhood holds all three voxels except the ends
    # voxel 0: neighbours {0, 1}; voxel 1: {0, 1, 2}; voxel 2: {1, 2}
    wlc = np.array([0.75, 1.0, 0.25])
    theta = np.array([0.2, 0.8, 0.4])
    nbh = [[0, 1], [0, 1, 2], [1, 2]]
    samples = np.array([10, 5, 0.0])
    mu = np.array([1, 0, 3])
    for i in range(3):
        theta_max = theta[nbh[i]].max()
        wlg = theta[i] / theta_max
        denom = wlc[nbh[i]].max() + 1.0 + lod
        wl = (wlc[i] + wlg + lod) / denom                       # (1)
        wdn = samples[i] / samples[nbh[i]].max()
        wdg = wlg / 2 ** mu[i]
        wl2 = (wlc[i] + wdg + lod) / denom                      # (2)
        P = wl - wl2 * wdn                                      # (3)
        assert got["wl"][i] == pytest.approx(wl)
        assert got["wl_prime"][i] == pytest.approx(wl2)
        assert got["wd_prime"][i] == pytest.approx(wdn)
        assert got["priority"][i] == pytest.approx(P)
    # the corner table of the paper, and a voxel found only by samples
    np.testing.assert_array_equal(manager.corner_workload(np.arange(9), np.zeros(9, bool)),
                                  [0, 0.25, 0.5, 0.75, 1.0, 0.75, 0.5, 0.25, 0])
    assert manager.corner_workload(np.array([0]), np.array([True]))[0] == 0.25


def test_same_seed_same_output_and_resumable(load_example):
    m = load_example("pear")
    view = View(eye=(5, -7, 3))
    a = run(m, view, resolution=14, seed=3)
    b = Session(m, view, Settings(resolution=14, seed=3))
    b.request("OUTLINES")
    lengths = []
    while b.step():                       # step by step, reading progress on the way
        lengths.append(b.progress()["outline_length"])
    assert b.progress()["tasks_left"] == 0 and b.iteration == a.iteration
    oa, ob = a.outlines(), b.outlines()
    assert len(oa) == len(ob) and len(oa) >= 2
    for x, y in zip(oa, ob):
        assert x.kind == y.kind and np.array_equal(x.points, y.points)
    assert {o.kind for o in oa} == {"silhouette", "crease"}     # the bite's rim is a crease


def test_find_features_in_a_region_explores_only_there(load_example):
    m = load_example("pear")
    s = Session(m, View(eye=(5, -7, 3)), Settings(resolution=14, seed=1))
    region = Region(sphere=((0.0, 0.0, 1.6), 0.4))       # around the stalk
    s.request("FIND_FEATURES", region)
    assert s.explorers.queue
    queued = s.bb.lo + (s.bb.vox["ijk"][s.explorers.queue] + 0.5) * s.h
    assert np.all(region.contains(queued))
    s.run(iterations=200)
    assert s.bb.vox["path_steps"].sum() > 0


KINDS_ARE = "must be one or more of silhouette, crease, curvature, suggestive, ridges, got "


@pytest.mark.parametrize("kw, msg", [(dict(resolution=200), "resolution must be a whole number from 8 to 128"),
                                     (dict(agents=0), "agents must be"), (dict(lod=float("nan")), "lod must be"),
                                     (dict(kinds=("edges",)), KINDS_ARE + "edges"),
                                     (dict(kinds=()), KINDS_ARE + "none")])
def test_bad_settings_are_named(kw, msg):
    with pytest.raises(ValueError, match=msg):
        Session(model_of({"type": "point", "center": [0, 0, 0], "radius": 1}), View(direction=(0, 0, 1)),
                Settings(**kw))


def test_bad_requests_and_regions():
    s = Session(model_of({"type": "point", "center": [0, 0, 0], "radius": 1}), View(direction=(0, 0, 1)),
                Settings(resolution=8))
    with pytest.raises(ValueError, match="unknown request 'DRAW'"):
        s.request("DRAW")
    with pytest.raises(ValueError, match="radius must be > 0"):
        Region(sphere=((0, 0, 0), -1))
    with pytest.raises(ValueError, match="exactly one of eye"):
        View()


BODY = {"type": "box", "center": [0, 0, 0], "half_size": [1, 1, 1], "radius": 0.15}
POCKET = {"type": "box", "center": [0, -1.1, 0], "half_size": [0.3, 0.3, 0.3], "radius": 0.08}


@pytest.mark.parametrize("root", [BODY, {"type": "difference", "children": [BODY, POCKET]}],
                         ids=["rounded box", "box with a pocket"])
@pytest.mark.parametrize("res", [8, 12])
def test_rough_polygonisation_vertices_lie_on_the_surface(root, res):
    """A compact kernel is far from linear across a coarse cell: interpolated crossings
    (and their means) fell on the flat core of the box, f = 1 and no gradient (every
    vertex of the rounded box at 8^3)."""
    from blobtree_ink.blackboard.polygonise import polygonise
    ev = M.Evaluator(model_of(root))
    mesh = polygonise(ev, res)
    f, g = ev.field_grad(mesh.vertices)
    assert len(f) > 100
    assert np.abs(f - ev.iso).max() < 1e-6
    assert np.linalg.norm(g, axis=1).min() > 1e-3


@pytest.mark.parametrize("res", [8, 12, 20])
def test_sharp_rim_of_a_pocket_is_traced_closed(res):
    """A box cut into a box: the pocket's rim is a sharp convex edge (90 degrees). The
    bracket end over the pocket lies on the subtracted box's flat core: projected
    straight back it lands on the edge, and a trace would be lost after a step or two."""
    s = run(model_of({"type": "difference", "children": [BODY, POCKET]}), View(eye=(2.0, -6.0, 1.5)),
            resolution=res, kinds=("crease",))
    outs = s.outlines()
    assert len(outs) == 1 and outs[0].closed
    rim = outs[0]
    # on both children's surfaces: the body's face and the pocket's wall
    for child in (BODY, POCKET):
        f = M.Evaluator(model_of(child)).field(rim.points)
        assert np.abs(f - 0.5).max() < 1e-6
    # a 0.6 square offset by the wall's distance from the pocket's core: straight sides
    # and quarter circles at the corners
    off = 0.08 * K
    perimeter = 4 * 0.6 + 2 * math.pi * off
    assert 0.97 * perimeter < rim.length <= perimeter
    assert np.allclose(rim.points[:, 1], -(1 + 0.15 * K), atol=1e-6)


def test_a_feature_smaller_than_a_cell_is_seeded_from_the_corners_of_flagged_voxels():
    """The same small sphere: at initialisation the flagged voxels around it, where no
    polygon edge found a silhouette point, get one from their projected corners (a
    bracket whose ends face the eye and away); traced with no explorer at all, it is
    the sphere's closed silhouette circle."""
    c = np.array([0.0, -1.0, 0.1])
    model = model_of({"type": "union", "children": [{"type": "point", "center": [0, 0, 0], "radius": 1.6},
                                                    {"type": "point", "center": c.tolist(), "radius": 0.2}]})
    eye = np.array([0.0, -6.0, 0.5])
    view = View(eye=tuple(eye))
    rho = 0.2 * K
    plain = Session(model, view, Settings(resolution=12, explore_detail=False))
    s = Session(model, view, Settings(resolution=12))
    sil = KIND_ID["silhouette"]

    def near_small(sess):
        f = sess.bb.feat
        return np.flatnonzero((f["kind"] == sil) & (np.linalg.norm(f["pos"] - c, axis=1) < 2 * rho))

    assert len(near_small(plain)) == 0
    ids = near_small(s)
    assert len(ids) > 0
    f = s.bb.feat
    for end in ("a", "b"):
        np.testing.assert_allclose(s.ev.field(f[end][ids]), s.ev.iso, atol=1e-9)
    na = s.surface.normals(s.ev.field_grad(f["a"][ids])[1])
    nb = s.surface.normals(s.ev.field_grad(f["b"][ids])[1])
    fa = np.einsum("ij,ij->i", na, view.towards_eye(f["a"][ids]))
    fb = np.einsum("ij,ij->i", nb, view.towards_eye(f["b"][ids]))
    assert np.all((fa > 0) != (fb > 0))
    s._detail = np.zeros(0, np.int64)          # no exploration: the corner seeds alone
    s.request("OUTLINES")
    s.run()
    assert s.done and len(s.explorers.explored) == 0
    small = [o for o in s.outlines() if np.linalg.norm(o.points - c, axis=1).max() < 2 * rho]
    assert len(small) == 1 and small[0].closed
    np.testing.assert_allclose(np.linalg.norm(small[0].points - c, axis=1), rho, atol=1e-6)


def test_a_feature_smaller_than_a_cell_is_found_by_exploring_flagged_voxels():
    """A small sphere near a big one: no polygon edge of a 12^3 grid crosses its
    silhouette; the voxels whose corner normals disagree on facing the eye are explored
    once the edge seeds are traced, and its silhouette circle is found and closed."""
    c = np.array([0.0, -1.0, 0.1])      # where no polygon edge meets it (whether one does is chance)
    model = model_of({"type": "union", "children": [{"type": "point", "center": [0, 0, 0], "radius": 1.6},
                                                    {"type": "point", "center": c.tolist(), "radius": 0.2}]})
    eye = np.array([0.0, -6.0, 0.5])
    rho = 0.2 * K
    edges_only = run(model, View(eye=tuple(eye)), resolution=12, explore_detail=False)
    assert all(np.linalg.norm(o.points - c, axis=1).min() > 2 * rho for o in edges_only.outlines())
    s = run(model, View(eye=tuple(eye)), resolution=12)
    assert len(s.explorers.explored) > 0
    small = [o for o in s.outlines() if np.linalg.norm(o.points - c, axis=1).max() < 2 * rho]
    assert len(small) == 1 and small[0].closed
    o = small[0]
    np.testing.assert_allclose(np.linalg.norm(o.points - c, axis=1), rho, atol=1e-6)
    v = (eye - o.points) / np.linalg.norm(eye - o.points, axis=1, keepdims=True)
    assert np.abs(np.einsum("ij,ij->i", o.normals, v)).max() < 1e-6
    d = np.linalg.norm(eye - c)
    circle = 2 * math.pi * rho * math.sqrt(1 - (rho / d) ** 2)
    assert 0.95 * circle < o.length <= circle


def test_silhouette_arcs_are_seeded_where_a_traced_crease_meets_them():
    """Two overlapping balls (a union): each ball's silhouette runs from the crease circle
    to the crease circle. With every polygon-edge silhouette seed withdrawn and no
    exploration, the silhouettes are found only by the crease trace identifying where a
    sheet's normal turns from facing the eye to facing away; they must then be traced
    in full and exactly."""
    c0, c1, R0, R1 = np.array([0.0, 0, 0]), np.array([0.9, 0.0, 0.0]), 1.5, 1.2
    root = {"type": "union", "children": [{"type": "point", "center": list(c0), "radius": R0},
                                          {"type": "point", "center": list(c1), "radius": R1}]}
    eye = np.array([0.45, -8.0, 1.5])
    view = View(eye=tuple(eye))
    s = Session(model_of(root), view, Settings(resolution=12, explore_detail=False))
    s.request("OUTLINES")
    sil_id = KIND_ID["silhouette"]
    s.bb.feat.cols["used"][np.flatnonzero(s.bb.feat["kind"] == sil_id)] = True
    s.run()
    assert s.done
    sil = [o for o in s.outlines() if o.kind == "silhouette"]
    assert sil
    for o in sil:
        check_on_surface(s, o)
        assert np.abs(np.einsum("ij,ij->i", o.normals, view.towards_eye(o.points))).max() < 1e-6
    pts = np.concatenate([polyline_samples(o) for o in sil])
    for c, R, oc, oR in ((c0, R0, c1, R1), (c1, R1, c0, R0)):
        r, d = K * R, np.linalg.norm(eye - c)
        axis = (eye - c) / d
        ref = circle(c + r * r / d * axis, axis, r * math.sqrt(1 - r * r / (d * d)))
        ref = ref[np.linalg.norm(ref - oc, axis=1) > K * oR + 0.02]    # the arc outside the other ball
        worst, covered = coverage(pts, ref, 0.01 * r)
        assert len(ref) > 100 and covered > 0.97, (worst, covered)
