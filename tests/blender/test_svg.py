"""grease_pencil.svg: the drawing's strokes on an SVG page, projected through a camera
(plain numpy; the command line's outputs use it)."""
import xml.etree.ElementTree as ET
from importlib import import_module

import numpy as np
import pytest

AXES = np.eye(3)                     # right x, up y, looking down -z


@pytest.fixture
def svg(ext):
    return import_module(f"{ext.__name__}.grease_pencil.svg")


@pytest.fixture
def Stroke(ext):
    return import_module(f"{ext.__name__}.strokes.data").Stroke


def test_a_lens_maps_its_frame_onto_the_page(svg):
    """The frame's centre is the page's, its edges the page's edges (y down); a lens
    shift moves the frame's centre off the axis; an orthographic lens does not divide
    by the depth; a point behind the camera is refused."""
    lens = svg.Lens(np.zeros(3), AXES, centre=(0.0, 0.0), half=(0.5, 0.25))
    page, per_unit = lens.project([[0, 0, -4.0], [2.0, 1.0, -4.0], [-2.0, -1.0, -4.0]])
    np.testing.assert_allclose(page, [[0.5, 0.5], [1.0, 0.0], [0.0, 1.0]])
    np.testing.assert_allclose(per_unit, 1 / (2 * 0.5 * 4.0))        # a unit across at depth 4: a quarter page
    shifted = svg.Lens(np.zeros(3), AXES, centre=(0.1, 0.0), half=(0.5, 0.25))
    np.testing.assert_allclose(shifted.project([[0.4, 0, -4.0]])[0], [[0.5, 0.5]])
    ortho = svg.Lens(np.zeros(3), AXES, centre=(0.0, 0.0), half=(2.0, 1.0), ortho=True)
    np.testing.assert_allclose(ortho.project([[2.0, -1.0, -50.0]])[0], [[1.0, 1.0]])
    with pytest.raises(ValueError, match="behind the camera"):
        lens.project([[0, 0, 1.0]])


def test_the_page_holds_a_path_per_stroke_and_a_circle_per_stipple(svg, Stroke, tmp_path):
    lens = svg.Lens(np.zeros(3), AXES, centre=(0.0, 0.0), half=(0.5, 0.5))
    line = Stroke(np.array([[-1.0, 0, -4], [1.0, 0, -4]]), np.full(2, 0.01), np.array([1.0, 0.5]), cyclic=True)
    dot = Stroke(np.array([[0.0, 1.0, -4]]), np.full(1, 0.02), np.ones(1), dots=True)
    path = tmp_path / "page.svg"
    svg.write(path, {"Silhouette": [line], "Hatching": [], "Stipples": [dot]}, lens, (400, 400), (0.02, 0.02, 0.03))
    root = ET.parse(path).getroot()
    assert root.get("width") == "400px" and root.get("viewBox") == "0 0 400 400"
    groups = {g.get("id"): g for g in root if g.tag.endswith("g")}
    assert set(groups) == {"layer.Silhouette", "layer.Stipples"}                 # an empty layer writes nothing
    assert groups["layer.Silhouette"].get("stroke") == "#272730"                  # the ink in sRGB
    (p,) = list(groups["layer.Silhouette"])
    assert p.get("d") == "M100.000,200.000L300.000,200.000Z"
    assert float(p.get("stroke-width")) == pytest.approx(2 * 0.01 / 4 * 400)      # the width on the page
    assert float(p.get("stroke-opacity")) == pytest.approx(0.75)
    (c,) = list(groups["layer.Stipples"])
    assert (float(c.get("cx")), float(c.get("cy")), float(c.get("r"))) == pytest.approx((200.0, 100.0, 2.0))
