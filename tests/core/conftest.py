"""Core tier: plain pytest, numpy only. The pure packages are imported as
``blobtree_ink.*`` through tools/pure.py (never the bpy-importing root __init__)."""
import os
import sys

import numpy as np
import pytest

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(REPO, "tools"))
sys.path.insert(0, os.path.join(REPO, "tests"))     # helpers shared by the tiers (strokes_match)
import pure  # noqa: E402

pure.install()
assert "bpy" not in sys.modules

EXAMPLES = os.path.join(REPO, "examples")
PAPER_MODELS = ("pear", "jug", "heart", "train", "shell")
ALL_MODELS = ("sphere", "two_spheres", "torus", "csg_difference", "csg_union") + PAPER_MODELS


def example_path(name):
    return os.path.join(EXAMPLES, f"{name}.json")


@pytest.fixture(scope="session")
def load_example():
    from blobtree_ink import model as M
    cache = {}

    def get(name):
        if name not in cache:
            cache[name] = M.load(example_path(name))
        return cache[name]
    return get


def shown_strokes(ev, eye, kinds, layer, X):
    """The strokes of ``layer`` an outline illustration of ``ev`` (tracing ``kinds``,
    grid 20) draws from ``eye``, checked against the traced points X of its kind: no
    speck (shorter than strokes.style.SPECK trace steps), every stroke point visible
    but the ends (where a line goes behind the surface, on the edge of what shows),
    and none of X's hidden points among them. Returns the strokes."""
    from blobtree_ink import pipeline as PL
    from blobtree_ink.agents import Settings
    from blobtree_ink.blackboard.view import View
    from blobtree_ink.strokes import style as ST
    from blobtree_ink.strokes.visibility import visible
    job = PL.Job(ev, View(eye=eye), None, ST.style("outlines"), (PL.Request("OUTLINES"),), 0,
                 Settings(resolution=20, kinds=kinds))
    ill = PL.Illustration(job)
    strokes = ill.run().strokes.layers[layer]
    P = np.concatenate([st.points for st in strokes])
    lengths = [np.linalg.norm(np.diff(st.points, axis=0), axis=1).sum() for st in strokes]
    assert min(lengths) >= ST.SPECK * ill.session.step_len
    assert visible(ev, np.concatenate([st.points[1:-1] for st in strokes]), eye).all()
    hidden = X[~visible(ev, X, eye)]
    assert np.linalg.norm(hidden[:, None] - P[None], axis=2).min() > 1e-6      # the hidden points are gone
    return strokes


def pytest_sessionfinish(session, exitstatus):
    assert "bpy" not in sys.modules, "the core tier imported bpy"
