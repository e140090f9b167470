"""Silhouettes beside traced silhouettes (agents/beside.py): the shell's sutures fold
the surface so that silhouettes run side by side, or beside a crease, closer than a
voxel, where polygon edges give no seed; stepping sideways from the traced ones finds
more of them, and every point they add is a silhouette point."""
import numpy as np

from blobtree_ink import model as M
from blobtree_ink.agents import Session, Settings
from blobtree_ink.agents import session as session_module
from blobtree_ink.blackboard.polygonise import surface_box
from blobtree_ink.blackboard.view import View


def traced(model, view):
    s = Session(model, view, Settings(resolution=28))
    s.request("OUTLINES")
    while not s.done:
        s.step()
    return s


def silhouette_points(s):
    return np.concatenate([o.points for o in s.outlines() if o.kind == "silhouette"])


def test_sideways_steps_find_silhouettes_the_polygon_edges_missed(load_example, monkeypatch):
    model = load_example("shell")
    ev = M.Evaluator(model)
    lo, hi = surface_box(ev)
    d = np.array([1.0, -1.4, 0.8]) / np.linalg.norm([1.0, -1.4, 0.8])
    view = View(eye=tuple(0.5 * (lo + hi) + 1.5 * np.linalg.norm(hi - lo) * d))
    real = session_module.seeds_beside_silhouettes
    added = []

    def counted(*args):
        added.append(real(*args))
        return added[-1]
    monkeypatch.setattr(session_module, "seeds_beside_silhouettes", counted)
    probed = traced(model, view)
    assert len(added) == 1 and added[0] > 0          # once, when the edge seeds were traced
    monkeypatch.setattr(session_module, "seeds_beside_silhouettes", lambda *args: 0)
    plain = traced(model, view)
    A, B = silhouette_points(probed), silhouette_points(plain)
    h = probed.h
    # what the plain run traced is all there
    assert np.quantile(np.linalg.norm(B[:, None] - A[None], axis=2).min(axis=1), 0.98) < 0.3 * h
    # and more: points a quarter voxel or more from every point of the plain run
    new = A[np.linalg.norm(A[:, None] - B[None], axis=2).min(axis=1) > 0.25 * h]
    assert len(new) >= 10
    # silhouette points: on the surface, n.v = 0
    f, g = ev.field_grad(new)
    n = -g / np.linalg.norm(g, axis=1, keepdims=True)
    assert np.abs(f - ev.iso).max() < 1e-9
    assert np.abs(np.einsum("ij,ij->i", n, view.towards_eye(new))).max() < 1e-6


def test_nothing_beside_a_sphere_silhouette():
    """A sphere's silhouette has no neighbour: no seeds."""
    from test_massris import model_of
    s = traced(model_of({"type": "point", "center": [0, 0, 0], "radius": 1.0}), View(eye=(0.3, -4.0, 1.0)))
    assert len(silhouette_points(s)) > 20
    assert session_module.seeds_beside_silhouettes(s.outlines(), s.surface, s.bb, s.traces.traced, s.step_len,
                                                   s.settings.crease_angle) == 0
