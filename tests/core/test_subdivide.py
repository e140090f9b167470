"""Voxel subdivision (blackboard.subdivide): a wheel's holes, smaller than a cell of the
rough grid, get feature points (their crease circles, their walls' silhouettes) from the
fine cells of the voxels around them, and are traced at that scale; outlines traced at
different scales are stitched apart."""
import numpy as np

from blobtree_ink.agents import Session, Settings
from blobtree_ink.agents.outline import Outline
from blobtree_ink.blackboard.subdivide import _closest_pairs, fine_features
from blobtree_ink.blackboard.view import View

from test_massris import K, model_of

HOLES = np.array([[0.55, 0.0, 0.0], [-0.55, 0.0, 0.0]])
HALF = 0.12 * K                      # the disc's half thickness (the faces at y = +-HALF)
HOLE_R = 0.147 * K                   # the holes' balls
RING = np.sqrt(HOLE_R ** 2 - HALF ** 2)   # the crease circles' radius, on each face
VIEW = View(eye=(1.5, -5.0, 2.5))


def wheel():
    return model_of({"type": "difference", "children": [
        {"type": "disc", "center": [0, 0, 0], "normal": [0, 1, 0], "disc_radius": 1.0, "radius": 0.12},
        *({"type": "point", "center": c.tolist(), "radius": 0.147} for c in HOLES)]})


def traced_wheel(**kw):
    s = Session(wheel(), VIEW, Settings(resolution=8, **kw))
    s.request("OUTLINES")
    s.run()
    assert s.done
    return s


def near_holes(outlines, kind):
    """Points of the outlines of a kind within twice a ring's radius of a hole centre, by hole."""
    P = np.concatenate([o.points for o in outlines if o.kind == kind] or [np.zeros((0, 3))])
    return [P[np.linalg.norm(P - c, axis=1) < 2 * RING] for c in HOLES]


def test_fine_cells_find_the_creases_of_a_hole_smaller_than_a_cell():
    s = Session(wheel(), VIEW, Settings(resolution=8, subdivide=0))
    assert 2 * RING < s.h                                   # the hole is inside one cell
    box = np.array([(x, y, z) for x in (-1, 0, 1) for y in (-1, 0, 1) for z in (-1, 0, 1)]) * HOLE_R
    ijk = np.unique(s.bb.voxel_of((HOLES[:, None] + box[None]).reshape(-1, 3)), axis=0)   # the voxels the holes touch
    found = fine_features(s.ev, s.bb.lo, s.h, ijk, 6, VIEW, s.settings.crease_angle)
    pos, a, b = found["crease"]
    assert len(pos) >= 4
    # every bracket: both ends on the surface, one on a face and one on the hole's wall
    np.testing.assert_allclose(s.ev.field(np.concatenate([a, b])), s.ev.iso, atol=1e-7)
    near = np.linalg.norm(pos[:, None] - HOLES[None], axis=2).min(axis=1) < 2 * RING
    assert near.all()
    assert np.all(np.linalg.norm(a - b, axis=1) < np.sqrt(3) * s.h / 6 + 1e-12)     # within a fine cell
    # both faces of both holes
    for c in HOLES:
        mine = pos[np.linalg.norm(pos - c, axis=1) < 2 * RING]
        assert (mine[:, 1] > 0).any() and (mine[:, 1] < 0).any()


def test_a_session_traces_the_walls_of_sub_cell_holes_at_the_fine_scale():
    """The holes' walls (the subtracted balls between the disc's faces) show a
    silhouette from this view; seeded in the fine cells, they are traced with the fine
    cells' step: exact silhouette points on each ball, between the faces."""
    plain = traced_wheel(subdivide=0)
    # without subdivision explorers on the walls find a few coarse pieces at most
    assert max(len(p) for p in near_holes(plain.outlines(), "silhouette")) < 20
    s = traced_wheel()
    for c, P in zip(HOLES, near_holes(s.outlines(), "silhouette")):
        assert len(P) >= 20
        f, g = s.ev.field_grad(P)
        np.testing.assert_allclose(f, s.ev.iso, atol=1e-9)
        n = -g / np.linalg.norm(g, axis=1, keepdims=True)
        np.testing.assert_allclose(np.einsum("ij,ij->i", n, VIEW.towards_eye(P)), 0.0, atol=1e-6)
        np.testing.assert_allclose(np.linalg.norm(P - c, axis=1), HOLE_R, atol=1e-6)      # on the hole's ball
        assert np.all(np.abs(P[:, 1]) <= HALF + 1e-6)                                    # between the faces
    for c in HOLES:                                            # traced at the fine cells' scale
        fine = [o for o in s.outlines() if o.step < s.step_len and np.linalg.norm(o.points - c, axis=1).max() < 2 * RING]
        assert sum(len(o.points) for o in fine) >= 20
    fine = [o for o in s.outlines() if o.step < s.step_len]
    steps = np.concatenate([np.linalg.norm(np.diff(o.points, axis=0), axis=1) for o in fine])
    assert steps.max() < 0.1 * 2 * np.pi * HOLE_R              # dense enough to draw a small curve


def test_outlines_of_different_scales_are_stitched_apart():
    """Two small rings a coarse step apart: stitched at the coarse scale they would be
    pooled into one polyline; each stays its own closed loop."""
    s = Session(wheel(), VIEW, Settings(resolution=8))
    t = np.linspace(0, 2 * np.pi, 40, endpoint=False)
    ring = np.stack([0.02 * np.cos(t), np.zeros_like(t), 0.02 * np.sin(t)], axis=1)
    small = 0.3 * 0.02 * 2 * np.pi / 40 / 0.3                  # the rings' point spacing as their step
    s.traces.done = [Outline("crease", ring + [0.0, 0.0, 0.0], np.ones_like(ring), True, small),
                       Outline("crease", ring + [0.0, 0.05, 0.0], np.ones_like(ring), True, small)]
    out = s.outlines()
    assert 0.05 < 2.5 * s.step_len                              # close enough to pool at the coarse scale
    assert len(out) == 2 and all(o.closed and len(o.points) == 40 for o in out)
    assert {round(float(o.points[:, 1].mean()), 9) for o in out} == {0.0, 0.05}


def test_the_crease_circles_of_sub_cell_holes_are_traced_on_the_analytic_circles():
    """A hole's rim is a sharp wedge (the face and the hole's ball meet at about 38
    degrees): where the two tangent planes meet lies beyond the bracket's ends, and the
    crease estimate there is what makes its brackets converge (the midpoint alone let
    all of them stall). The rims facing the eye are traced all round."""
    s = traced_wheel()
    for c, P in zip(HOLES, near_holes(s.outlines(), "crease")):
        assert len(P) >= 20
        np.testing.assert_allclose(s.ev.field(P), s.ev.iso, atol=1e-9)
        np.testing.assert_allclose(np.abs(P[:, 1]), HALF, atol=1e-6)                   # on a face
        np.testing.assert_allclose(np.linalg.norm(P - c, axis=1), HOLE_R, atol=1e-6)    # and on the ball
        front = P[P[:, 1] < 0]                                                         # the face towards the eye
        ang = np.arctan2(front[:, 2] - c[2], front[:, 0] - c[0])
        hist, _ = np.histogram(ang, bins=8, range=(-np.pi, np.pi))
        assert np.all(hist > 0), hist


def test_the_closest_accepted_pair_of_a_cells_crossings_is_that_of_all_66_pairs():
    """_closest_pairs tries only the pairs among a cell's valid crossings (six for most
    cells): against every pair of the twelve edges, on random cells of two to twelve
    valid crossings, it picks the same pair (the first of equal ones), a on the edge
    that comes first, and no pair where none is accepted."""
    rng = np.random.default_rng(3)
    X = rng.random((400, 3))
    side = rng.random(400) < 0.5
    cells = 300
    E = rng.integers(0, 400, (cells, 12))
    count = rng.integers(2, 13, cells)
    valid = np.zeros((cells, 12), bool)
    for c in range(cells):
        valid[c, rng.choice(12, count[c], replace=False)] = True
    valid[:5] = False                               # a few cells with one usable crossing or none
    valid[:3, 7] = True
    E[5, :] = E[5, 0]                               # a cell whose crossings all lie on one side
    side[E[5, 0]] = True

    def accept(ia, ib):
        return side[ia] != side[ib]

    a, b = _closest_pairs(E, valid, X, accept)
    want_a, want_b = [], []
    for c in range(cells):
        best = None
        for i in range(12):
            for j in range(i + 1, 12):
                if valid[c, i] and valid[c, j] and side[E[c, i]] != side[E[c, j]]:
                    d = np.linalg.norm(X[E[c, i]] - X[E[c, j]])
                    if best is None or d < best[0]:
                        best = (d, i, j)
        if best is not None:
            want_a.append(X[E[c, best[1]]])
            want_b.append(X[E[c, best[2]]])
    assert 250 < len(want_a) < cells - 4
    np.testing.assert_array_equal(a, np.array(want_a))
    np.testing.assert_array_equal(b, np.array(want_b))


def test_a_small_silhouette_no_trace_reached_is_found_once_the_run_is_idle(monkeypatch):
    """A bead on a ball (their union: a crease ring where they meet), smaller than a cell
    of the rough grid, seen from above the front: no polygon edge crosses its small
    silhouette and no trace reaches (or loses) it. Once nothing else is left the voxels
    whose corners face both ways and whose normals spread past a right angle, with no
    traced silhouette inside, are resampled on fine cells: the bead's silhouette is
    traced, one line round the bead from the crease ring to the crease ring (where it
    goes behind the ball); a frame going on follows it and looks only in voxels the
    last did not; without that look, nothing is drawn there."""
    from blobtree_ink.agents import detail
    centre = np.array([0.0, 0.0, 1.08 * K])
    bead = model_of({"type": "union", "children": [{"type": "point", "center": [0, 0, 0], "radius": 1.0},
                                                  {"type": "point", "center": centre.tolist(), "radius": 0.1}]})
    view = View(eye=(0.0, -5.0, 1.5))

    def on_the_bead(eye=view, previous=None):
        s = Session(bead, eye, Settings(resolution=8), previous=previous, remember=True)
        s.request("OUTLINES")
        s.run()
        assert s.done
        near = [o for o in s.outlines() if (np.linalg.norm(o.points - centre, axis=1) < 0.3 * K).all()]
        return [o for o in near if o.kind == "silhouette"], [o for o in near if o.kind == "crease"], s
    found, ring, first = on_the_bead()
    assert len(found) == 1 and len(found[0].points) >= 8 and len(ring) == 1
    line = found[0]
    for end in (line.points[0], line.points[-1]):
        assert np.linalg.norm(ring[0].points - end, axis=1).min() < 2 * line.step
    # the next frame of a turning eye follows it (it looks only where the last did not)
    last = first.continuation()
    assert set(first._swept_rows.tolist()) == last.swept != set()
    found, _, going = on_the_bead(View(eye=(0.3, -5.0, 1.5)), last)
    assert len(found) == 1 and going.continuation().swept >= last.swept
    look = detail.unfound_silhouettes
    monkeypatch.setattr(detail, "unfound_silhouettes", lambda *a, **k: np.zeros(0, np.int64))
    found, _, bare = on_the_bead()
    assert found == []
    # where it looks: the bead's voxels, but those looked in already
    everywhere = lambda P: np.ones(len(P), bool)                        # noqa: E731
    rows = look(bare.bb, bare.surface, bare.settings, bare.outlines(), everywhere)
    assert 0 < len(rows) <= 8
    assert (np.linalg.norm(bare.bb.lo + (bare.bb.vox["ijk"][rows] + 0.5) * bare.bb.h - centre, axis=1)
            < 2 * bare.bb.h).all()
    assert len(look(bare.bb, bare.surface, bare.settings, bare.outlines(), everywhere, frozenset(rows.tolist()))) == 0
