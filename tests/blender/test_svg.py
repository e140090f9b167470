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


def test_a_tapered_stroke_is_a_path_per_stretch_of_like_width(svg, Stroke, tmp_path):
    """A hatching stroke that thins along its length is written as paths end to end,
    each of its stretch's width (within LIKE_WIDTH) and opacity: the page keeps the
    taper; a stroke of one width stays one path."""
    lens = svg.Lens(np.zeros(3), AXES, centre=(0.0, 0.0), half=(0.5, 0.5))
    x = np.linspace(-1.0, 1.0, 21)
    P = np.stack([x, np.zeros_like(x), np.full_like(x, -4.0)], axis=1)
    tapered = Stroke(P, np.linspace(0.02, 0.004, 21), np.linspace(1.0, 0.4, 21))
    even = Stroke(P + [0, 0.5, 0], np.full(21, 0.01), np.ones(21))
    path = tmp_path / "page.svg"
    svg.write(path, {"Hatching": [tapered, even]}, lens, (400, 400), (0.0, 0.0, 0.0))
    paths = list(next(g for g in ET.parse(path).getroot() if g.get("id") == "layer.Hatching"))
    pts = [[tuple(map(float, q.split(","))) for q in p.get("d")[1:].split("L")] for p in paths]
    widths = [float(p.get("stroke-width")) for p in paths]
    alphas = [float(p.get("stroke-opacity")) for p in paths]
    *taper, last = paths
    assert all(p.get("stroke-linecap") == "butt" for p in taper) and last.get("stroke-linecap") is None
    assert len(taper) >= 5 and pts[-1] == [(x, 150.0) for x in np.linspace(100.0, 300.0, 21)] and widths[-1] == 2.0
    assert all(a[-1] == b[0] for a, b in zip(pts[:-2], pts[1:-1]))                    # end to end
    assert [q for a in pts[:-1] for q in a[:-1]] + [pts[-2][-1]] == [(x, 200.0) for x in np.linspace(100.0, 300.0, 21)]
    assert np.all(np.diff(widths[:-1]) < 0) and np.all(np.diff(alphas[:-1]) < 0)      # thinner and lighter along it
    assert widths[0] == pytest.approx(2 * 0.0195 / 4 * 400, rel=0.08) and widths[-2] < 0.5 * widths[0]
    r = np.linspace(0.02, 0.004, 21)
    seg = 0.5 * (r[1:] + r[:-1])                                   # each segment's radius
    for a in pts[:-1]:                                             # a stretch's segments are alike
        i, j = round((a[0][0] - 100) / 10), round((a[-1][0] - 100) / 10)
        assert np.abs(seg[i:j] - seg[i]).max() <= svg.LIKE_WIDTH * seg[i] + 1e-12
