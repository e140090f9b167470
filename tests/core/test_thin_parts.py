"""Parts thinner than a grid cell: a disc lying between two grid planes has no sign
change on any grid edge, so the rough polygonisation misses it; probing the grid edges
(polygonise.thin_parts) finds it, and a MASSRIS session explores from there and traces
its rim."""
import numpy as np
import pytest

from blobtree_ink import model as M
from blobtree_ink.agents import Session, Settings, manager
from blobtree_ink.blackboard.polygonise import polygonise, thin_parts
from blobtree_ink.blackboard.view import View

from test_massris import K, model_of

DISC_C = np.array([2.4, 0.0, 0.0])
HALF = 0.12 * K          # half the disc's thickness (a disc skeleton with radius 0.12)


def disc_model(y):
    return model_of({"type": "union", "children": [
        {"type": "point", "center": [0.0, 0.0, 0.0], "radius": 1.6},
        {"type": "disc", "center": [DISC_C[0], y, 0.0], "normal": [0, 1, 0], "disc_radius": 0.45, "radius": 0.12}]})


@pytest.fixture(scope="module")
def missed():
    """The disc placed where the resolution-10 grid misses it (the first of a few
    offsets whose mesh has no vertex near the disc: where grid planes fall is exact
    arithmetic, so the choice is deterministic)."""
    for y in np.linspace(0.0, 0.3, 13):
        ev = M.Evaluator(disc_model(y))
        mesh = polygonise(ev, 10)
        near = np.linalg.norm(mesh.vertices - (DISC_C + [0, y, 0]), axis=1) < 0.8
        if not near.any():
            return y, ev, mesh
    raise AssertionError("every offset put a grid plane through the disc")


def test_probing_the_grid_edges_finds_a_disc_the_grid_missed(missed):
    y, ev, mesh = missed
    X, cells = thin_parts(ev, mesh)
    on_disc = np.linalg.norm(X - (DISC_C + [0, y, 0]), axis=1) < 0.8
    assert on_disc.sum() >= 4
    P = X[on_disc]
    np.testing.assert_allclose(ev.field(P), ev.iso, atol=1e-9)
    assert np.all(np.abs(P[:, 1] - y) <= HALF + 1e-9)           # on the disc's faces or rim
    # each point lies in its reported cell
    np.testing.assert_array_equal(cells[on_disc], np.floor((P - mesh.grid.lo) / mesh.grid.cell).astype(int))


def test_nothing_is_found_where_the_grid_saw_everything():
    ev = M.Evaluator(model_of({"type": "point", "center": [0, 0, 0], "radius": 1.0}))
    X, _ = thin_parts(ev, polygonise(ev, 12))
    assert len(X) == 0


def test_a_session_traces_the_rim_of_the_missed_disc(missed):
    y, ev, _ = missed
    centre = DISC_C + [0, y, 0]
    view = View(eye=(2.4, -6.0, 3.0))
    plain = Session(ev, view, Settings(resolution=10, explore_detail=False))
    plain.request("OUTLINES")
    plain.run()
    assert all(np.linalg.norm(o.points - centre, axis=1).min() > 0.8 for o in plain.outlines())
    s = Session(ev, view, Settings(resolution=10))
    s.request("OUTLINES")
    s.run()
    assert s.done
    rim = [o for o in s.outlines() if o.kind == "silhouette" and np.linalg.norm(o.points - centre, axis=1).max() < 0.8]
    assert rim
    pts = np.concatenate([o.points for o in rim])
    np.testing.assert_allclose(ev.field(pts), ev.iso, atol=1e-9)
    # the rim's silhouette runs all round the disc: its points spread over every
    # direction around the centre in the disc's plane
    ang = np.arctan2(pts[:, 2] - centre[2], pts[:, 0] - centre[0])
    hist, _ = np.histogram(ang, bins=8, range=(-np.pi, np.pi))
    assert np.all(hist > 0)


def _disc_surface_voxels(s, centre):
    """The blackboard's surface voxels within reach of the disc."""
    c = s.bb.lo + (s.bb.vox["ijk"][s.bb.surface_rows] + 0.5) * s.h
    return np.linalg.norm(c - centre, axis=1) < 0.8


def test_an_outline_request_probes_for_missed_sheets_once_the_polygon_seeds_are_traced(missed):
    """The probing and its explorers wait for the detail phase of an outline request
    (the polygon's own seeds find most outlines first); then the disc's voxels join the
    blackboard as surface voxels, their corners are searched for feature points like
    the polygon's, and explorers are queued there ahead of the flagged voxels. A
    find-features request wants the explorers at once."""
    y, ev, _ = missed
    centre = DISC_C + [0, y, 0]
    view = View(eye=(2.4, -6.0, 3.0))
    s = Session(ev, view, Settings(resolution=10))
    s.request("OUTLINES")
    assert not _disc_surface_voxels(s, centre).any() and not s.explorers.queue and not s.done
    before = len(s.bb.surface_rows)
    while s._detail is None:
        s.step()
    new = s.bb.surface_rows[before:]
    assert len(new) >= 2 and _disc_surface_voxels(s, centre)[before:].all()
    starts = [r for r, p in s.explorers.starts.items() if np.linalg.norm(p - centre) < 0.8]
    assert starts and set(starts) <= set(s.explorers.queue) | s.explorers.explored
    assert s.explorers.queue[:len(starts)] == sorted(starts, key=s.explorers.queue.index)     # ahead of the rest
    on_disc = np.linalg.norm(s.bb.feat["pos"][:s.bb.feat.n] - centre, axis=1) < 0.8
    assert on_disc.any()                                       # corner feature points of the disc's voxels
    # the new voxels have their priorities (equation 3), not the zeros they were appended with
    fresh = manager.priorities(s.bb, new, s.settings.lod)["priority"]
    assert len(s.priority) == s.bb.vox.n and (fresh > 0).any()     # (no corner inside: 0 from the table)
    np.testing.assert_allclose(s.priority[new], fresh)

    f = Session(ev, view, Settings(resolution=10))
    f.request("FIND_FEATURES")
    assert _disc_surface_voxels(f, centre).sum() >= 2
    assert any(np.linalg.norm(p - centre) < 0.8 for p in f.explorers.starts.values())
