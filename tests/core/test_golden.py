"""Golden drawings: three examples in three styles, drawn through the pipeline, match
their stored references stroke by stroke (tests/golden/cases.py; `tools/golden`
regenerates them). A change that alters a drawing shows here."""
import os
import sys

import numpy as np
import pytest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "golden"))
import cases  # noqa: E402
import strokes_match as SM  # noqa: E402


@pytest.mark.parametrize("style", cases.STYLES)
@pytest.mark.parametrize("example", cases.EXAMPLES)
def test_the_drawing_matches_its_reference(load_example, example, style):
    want = cases.load_reference(example, style)
    got, radius = cases.draw(load_example, example, style)
    assert SM.differences(want, got, cases.TOLERANCE * radius) == []
    assert {"Silhouette"} <= set(got) and len(got) >= 2           # outlines and the style's strokes


def test_the_comparison_sees_a_changed_drawing(load_example):
    """The tolerance lets rounding through, not a change: fewer strokes, strokes moved
    by a hundredth of the model's size, or thicker ones all differ."""
    want = cases.load_reference("pear", "hatched")
    got, radius = cases.draw(load_example, "pear", "hatched")
    fewer = dict(got, Hatching=got["Hatching"][: int(0.9 * len(got["Hatching"]))])
    moved = dict(got, Hatching=[(p + [0.01 * radius, 0, 0], r, o) for p, r, o in got["Hatching"]])
    thicker = dict(got, Hatching=[(p, 1.2 * r, o) for p, r, o in got["Hatching"]])
    for changed, what in ((fewer, "strokes against"), (moved, "points within"), (thicker, "median radius")):
        diff = SM.differences(want, changed, cases.TOLERANCE * radius)
        assert diff and all(d.startswith("Hatching") for d in diff) and any(what in d for d in diff)
    # the outline layers exactly: a lost layer, a lost stroke, one stroke's point moved
    no_crease = {k: v for k, v in got.items() if k != "Crease"}
    one_less = dict(got, Silhouette=got["Silhouette"][1:])
    p, r, o = got["Silhouette"][0]
    bent = dict(got, Silhouette=[(np.vstack([p[:1] + 0.01 * radius, p[1:]]), r, o)] + got["Silhouette"][1:])
    for changed in (no_crease, one_less, bent):
        assert SM.differences(want, changed, cases.TOLERANCE * radius)
