"""Core tier: plain pytest, numpy only. The pure packages are imported as
``blobtree_ink.*`` through tools/pure.py (never the bpy-importing root __init__)."""
import os
import sys

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


def pytest_sessionfinish(session, exitstatus):
    assert "bpy" not in sys.modules, "the core tier imported bpy"
