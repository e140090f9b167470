"""The illustration pipeline's requests: what each preset draws (the README's table),
the layers a request owns, regions that hold no surface, a style without strokes."""
import numpy as np
import pytest

from blobtree_ink import pipeline as PL
from blobtree_ink.agents import Region
from blobtree_ink.strokes import style as ST
from helpers import job_for

# the README's preset table: the layers each preset draws, besides the outlines
PRESET_LAYERS = {
    "outlines": set(),
    "stippled": {"Stipples"},
    "hatched": {"Hatching"},
    "flocked": {"Hatching"},
    "silhouette-shading": {"Chains"},
    "short-strokes": {"Short Strokes", "Stipples"},
    "technical": {"Hatching"},
    "contour": {"Hatching"},
}


def test_the_readme_table_names_every_preset():
    assert set(PRESET_LAYERS) == set(ST.STYLES)
    import os
    readme = open(os.path.join(os.path.dirname(__file__), "..", "..", "README.md")).read()
    for name in ST.STYLES:
        assert f"| `{name}` |" in readme


@pytest.mark.parametrize("preset", sorted(PRESET_LAYERS))
def test_each_preset_draws_its_layers(load_example, preset):
    res = PL.Illustration(job_for(load_example, "pear", preset, res=12)).run()
    drawn = {k for k, v in res.strokes.layers.items() if v}
    assert drawn - {"Silhouette", "Crease"} == PRESET_LAYERS[preset]
    assert {"Silhouette", "Crease"} <= drawn and not res.warnings


def test_technical_hatching_is_horizontal(load_example):
    """The technical look hatches along the level lines of the vertical axis: each
    stroke keeps its height while it runs across the surface."""
    res = PL.Illustration(job_for(load_example, "jug", "technical", res=14)).run()
    strokes = [s for s in res.strokes.layers["Hatching"] if len(s.points) >= 4]
    assert len(strokes) > 20
    rise = np.array([np.ptp(s.points[:, 2]) for s in strokes])
    run = np.array([np.linalg.norm(np.ptp(s.points[:, :2], axis=0)) for s in strokes])
    assert np.median(rise / run) < 0.1 and np.quantile(rise / run, 0.9) < 0.3
    # the same measure sees vertical strokes (the axis field along the vertical axis)
    upright = PL.Illustration(job_for(load_example, "jug", "technical", res=14, hatch_field="axis")).run()
    other = [s for s in upright.strokes.layers["Hatching"] if len(s.points) >= 4]
    assert np.median([np.ptp(s.points[:, 2]) / np.linalg.norm(np.ptp(s.points[:, :2], axis=0)) for s in other]) > 1


def test_requests_own_only_their_layers(load_example):
    outlines = job_for(load_example, "pear", "hatched", requests=[PL.Request("OUTLINES")])
    strokes = job_for(load_example, "pear", "stippled", requests=[PL.Request("PLACE_STROKES")])
    single = job_for(load_example, "pear", "hatched", requests=[PL.Request("SINGLE_STROKE", cursor=(0, -2, 0))])
    assert outlines.owned_layers() == ("Silhouette", "Crease") and outlines.appended_layers() == ()
    assert strokes.owned_layers() == ("Stipples",)
    assert single.owned_layers() == () and single.appended_layers() == ("Single Strokes",)
    res = PL.Illustration(strokes).run()
    assert set(res.owned) == {"Stipples"} and res.strokes.count("Silhouette") == 0


def test_a_region_without_surface_says_so_and_replaces_nothing(load_example):
    far = Region(sphere=((40.0, 0.0, 0.0), 1.0))
    job = job_for(load_example, "pear", "hatched", requests=[PL.Request("PLACE_STROKES", far)])
    res = PL.Illustration(job).run()
    assert res.owned == () and res.strokes.count() == 0
    assert res.warnings == ["the region holds no part of the model's surface: Place Strokes draws nothing"]
    near = Region(sphere=((0.0, 0.0, 0.0), 5.0))
    res = PL.Illustration(job_for(load_example, "pear", "hatched", requests=[PL.Request("PLACE_STROKES", near)])).run()
    assert res.owned == ("Hatching",) and res.strokes.count("Hatching") > 10 and not res.warnings


def test_a_style_without_strokes_draws_nothing_and_says_why(load_example):
    job = job_for(load_example, "pear", "outlines", requests=[PL.Request("PLACE_STROKES")])
    res = PL.Illustration(job).run()
    assert res.strokes.count() == 0 and res.owned == ()
    assert res.warnings and "the style draws no strokes" in res.warnings[0]
