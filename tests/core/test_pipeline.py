"""The illustration pipeline's requests: what each preset draws (the README's table),
the layers a request owns, regions that hold no surface, a style without strokes."""
import dataclasses

import numpy as np
import pytest

from blobtree_ink import model as M
from blobtree_ink import pipeline as PL
from blobtree_ink.agents import Region
from blobtree_ink.strokes import style as ST
from helpers import BALL, job_for


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


def test_the_job_leaves_compiling_framing_and_lighting_to_the_illustration(load_example):
    """A job can hold the model uncompiled, no view and no light: the illustration's
    initialisation (on a runner's worker) compiles it, frames it in a three-quarter view,
    lights it from the viewer's upper left or from a point light, and makes a region
    around a point from the model's size."""
    from blobtree_ink import model as M
    model = load_example("pear")
    near = PL.Around((0.0, -0.6, -0.2), 0.3)
    job = PL.Job(model, requests=(PL.Request("PLACE_STROKES", near),), style=ST.style("stippled"))
    ill = PL.Illustration(job)
    assert ill.ev is None and ill.eye is None
    ill.step()
    ev = M.Evaluator(model)
    centre, radius = PL.bounds(ev)
    np.testing.assert_allclose(ill.eye, PL.three_quarter_eye(centre, radius))
    np.testing.assert_allclose(ill.light, PL.default_light(centre, ill.eye))
    region = ill.requests[0].region
    assert region.sphere[1] == pytest.approx(0.3 * radius)
    res = ill.run()
    pts = np.concatenate([s.points for s in res.strokes.layers["Stipples"]])
    assert np.linalg.norm(pts - near.centre, axis=1).max() <= 0.3 * radius + 1e-9
    lamp = PL.Illustration(PL.Job(model, light_at=(centre[0], centre[1], centre[2] + 10.0)))
    lamp.step()
    np.testing.assert_allclose(lamp.light, [0.0, 0.0, 1.0], atol=1e-12)


@pytest.mark.parametrize("change, message", [
    (dict(light=(0, 0, 0)), "light direction must be three finite numbers, not all zero"),
    (dict(light=(0, 0, 1), light_at=(1, 1, 1)), "a light direction or a light position, not both"),
    (dict(seed=-1), "seed must be a whole number from 0"),
    (dict(requests=(PL.Request("OUTLINES"), PL.Request("OUTLINES"))), "each request at most once"),
    (dict(requests=(PL.Request("PLACE_STROKES", PL.Around((0, 0, np.nan), 0.2)),)), "region's centre"),
    (dict(model="pear.json"), "the model must be a model.Model or a model.Evaluator"),
    (dict(seconds=-2), "time budget must be a positive number"),
    (dict(occluders=("pear.json",)), "occluder 0 must be a .model, matrix. pair"),
    (dict(lines=(np.zeros((3, 3)),)), "lines drawn already must be strokes.data.Stroke values"),
    (dict(occluders=((M.from_dict(BALL), np.zeros((4, 4))),)), "occluder 0's matrix must be an invertible 4x4"),
    (dict(occluders=((M.from_dict(BALL), np.full((4, 4), np.nan)),)), "occluder 0's matrix must be an invertible"),
])
def test_bad_jobs_are_named(load_example, change, message):
    job = dataclasses.replace(PL.Job(load_example("pear")), **change)
    with pytest.raises(PL.JobError, match=message):
        PL.Illustration(job)


def test_a_single_stroke_sets_off_to_the_right_of_the_view(load_example):
    """A principal direction has no way of its own: the single stroke from a point goes
    the way that is to the view's right, wherever on the model the point is and however
    the eye looks at it (here from the front and from the left)."""
    from blobtree_ink import model as M
    from blobtree_ink.model.marks import surface_marks
    from blobtree_ink.pipeline import layers as LY
    ev = M.Evaluator(load_example("pear"))
    centre = 0.5 * (np.asarray(ev.bounds[0]) + np.asarray(ev.bounds[1]))
    st = ST.style("hatched")
    points = surface_marks(ev, 0.03 * ev.scale, 3).points[::20][:12]
    for eye in (centre + [0.0, -3.0 * ev.scale, 0.0], centre + [-3.0 * ev.scale, 0.0, 0.0]):
        cv = LY.Canvas(ev, eye, np.array([0.0, 0.0, 1.0]), 0.01, 0.02 * ev.scale)
        went = []
        for p in points:
            s = LY.single_stroke(cv, st, p)
            if s is not None:
                went.append(float(np.dot(s.points[1] - s.points[0], ST.view_right(eye, p))))
        assert len(went) >= 10 and all(w > 0 for w in went), went


def test_principal_strokes_do_not_kink_where_the_principal_directions_change_places(load_example):
    """Near an umbilic the two principal directions change places within a step; a
    smarticle following one keeps its heading there (a direction more than TURN from it
    is noise) instead of turning a right angle: no single stroke on the heart turns more
    than 60 degrees between two steps, and the flow field keeps a heading that a
    principal direction crosses."""
    from blobtree_ink import model as M
    from blobtree_ink.model.marks import surface_marks
    from blobtree_ink.pipeline import layers as LY
    from blobtree_ink.strokes import layers as SL
    flow = SL.direction_field("dir1")
    v = np.array([[1.0, 0.0, 0.0], [1.0, 0.0, 0.0]])
    c = {"dir1": np.array([[0.0, 1.0, 0.0], [np.cos(0.5), np.sin(0.5), 0.0]]), "k1": np.array([2.0, 2.0]),
         "k2": np.array([0.5, 0.5]), "velocity": v}
    np.testing.assert_array_equal(flow(None, None, c), [[1.0, 0.0, 0.0], [np.cos(0.5), np.sin(0.5), 0.0]])
    ev = M.Evaluator(load_example("heart"))
    centre = 0.5 * (np.asarray(ev.bounds[0]) + np.asarray(ev.bounds[1]))
    eye = centre + 3.0 * ev.scale * np.array([0.2, -0.9, 0.3])
    cv = LY.Canvas(ev, eye, np.array([0.0, 0.0, 1.0]), 0.01, 0.032 * ev.scale)
    turns = []
    for p in surface_marks(ev, 0.02 * ev.scale, 5).points[::9][:60]:
        s = LY.single_stroke(cv, ST.style("hatched"), p)
        if s is not None:
            d = np.diff(s.points, axis=0)
            d /= np.linalg.norm(d, axis=1)[:, None]
            turns.append(np.degrees(np.arccos(np.clip((d[1:] * d[:-1]).sum(1), -1, 1))).max(initial=0.0))
    assert len(turns) > 40 and max(turns) < 60.0, sorted(turns)[-5:]


def test_stipples_drawn_in_parts_keep_apart_across_the_parts(load_example, monkeypatch):
    """The stipple layer is drawn in parts of its marks; a part's dots keep apart on the
    paper from the dots the parts before it drew, not only from each other: none touch."""
    from blobtree_ink.pipeline import layers as LY
    from blobtree_ink.strokes import stipples as L
    monkeypatch.setattr(LY, "CHUNK", 150)
    ill = PL.Illustration(job_for(load_example, "pear", "stippled", requests=[PL.Request("PLACE_STROKES")]))
    parts = 0
    while ill.step():
        parts += ill.stage == "stipples"
    dots = ill.result().strokes.layers["Stipples"]
    assert parts > 3 and len(dots) > 500
    P = np.concatenate([s.points for s in dots])
    U, a = L.on_paper(P, [s.radius[0] for s in dots], ill.eye)
    d = np.linalg.norm(U[:, None] - U[None], axis=2) + np.eye(len(U)) * 1e9
    assert (d >= (a[:, None] + a[None]) * (1 - 1e-9)).all()


def test_two_eyes_see_the_model_alike_when_close_in_direction_and_distance():
    """framing.same_view: eyes within VIEW_ANGLE degrees of direction from the model's
    centre and VIEW_DISTANCE of distance see it alike; the centre counts, not the origin."""
    from blobtree_ink.pipeline import framing as FR
    centre = np.array([1.0, 2.0, 3.0])

    def eye(degrees, distance=10.0):
        a = np.radians(degrees)
        return centre + distance * np.array([np.cos(a), np.sin(a), 0.0])
    assert FR.same_view(eye(0), eye(0.9 * FR.VIEW_ANGLE), centre)
    assert not FR.same_view(eye(0), eye(1.1 * FR.VIEW_ANGLE), centre)
    assert FR.same_view(eye(0), eye(0, 10.0 * (1 + 0.9 * FR.VIEW_DISTANCE)), centre)
    assert not FR.same_view(eye(0), eye(0, 10.0 * (1 + 1.1 * FR.VIEW_DISTANCE)), centre)
    assert not FR.same_view(eye(0), eye(180), centre)
    assert FR.same_view(centre, centre, centre) and not FR.same_view(centre, eye(0), centre)


def test_a_crop_cuts_the_same_view_closer_about_the_points():
    """framing.crop: from a camera at the eye (its axes right, up, backwards), the lens
    (the tangent of the longer side's half-angle) and shift that frame the points with
    the margin, centred; a wide render frames them by their height when it must."""
    from blobtree_ink.pipeline import framing as FR
    axes = np.eye(3)                                             # looking down -z, up +y
    pts = np.array([[1.0, -1.0, -10.0], [3.0, 1.0, -10.0], [2.0, 0.0, -10.0]])
    tan_half, sx, sy = FR.crop(axes, np.zeros(3), pts)
    assert tan_half == pytest.approx(FR.MARGIN * 0.1)            # the points span 0.1..0.3 and -0.1..0.1
    assert sx == pytest.approx(0.2 / (2 * tan_half)) and sy == pytest.approx(0.0)
    # in the frame so cut, every point lies within 1/MARGIN of the centre's half-width
    uv = pts[:, :2] / 10.0 - 2 * tan_half * np.array([sx, sy])
    assert np.abs(uv).max() == pytest.approx(tan_half / FR.MARGIN)
    wide, _, _ = FR.crop(axes, np.zeros(3), pts, aspect=2.0)      # twice as wide: the height decides
    assert wide == pytest.approx(FR.MARGIN * 0.2)
    tall, _, _ = FR.crop(axes, np.zeros(3), pts, aspect=0.5)      # twice as tall: the width decides
    assert tall == pytest.approx(FR.MARGIN * 0.2)
    assert FR.crop(axes, np.zeros(3), pts[:1], least=0.05)[0] == 0.05    # one point: no closer than asked
    with pytest.raises(ValueError, match="in front of the camera"):
        FR.crop(axes, np.zeros(3), pts * np.array([1, 1, -1]))


def test_the_image_plane_is_one_unit_ahead_or_at_any_depth():
    """framing.image_plane, the one projection of the crop and the SVG page: a
    perspective camera's points divided by their depth, an orthographic one's as they
    are; a point behind a perspective camera is an error."""
    from blobtree_ink.pipeline import framing as FR
    axes = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])   # right +y, up +z, backwards +x
    eye = np.array([5.0, 0.0, 0.0])
    pts = np.array([[0.0, 1.0, 2.0], [-5.0, -3.0, 0.5]])                  # 5 and 10 ahead
    uv, depth = FR.image_plane(axes, eye, pts)
    assert np.allclose(depth, [5.0, 10.0]) and np.allclose(uv, [[0.2, 0.4], [-0.3, 0.05]])
    uv, depth = FR.image_plane(axes, eye, pts, ortho=True)
    assert np.allclose(depth, 1.0) and np.allclose(uv, [[1.0, 2.0], [-3.0, 0.5]])
    with pytest.raises(ValueError, match="behind the camera"):
        FR.image_plane(axes, eye, [[6.0, 0.0, 0.0]])


def _project(rel, t, offset):
    """Points about a centre (camera axes) seen from a camera t back on the line through
    the centre and the frame's centre (``offset``, one unit ahead): their image one unit
    ahead, about the frame's centre."""
    cam = t * np.array([-offset[0], -offset[1], 1.0])
    q = rel - cam
    return q[:, :2] / -q[:, 2:] - np.asarray(offset)


@pytest.mark.parametrize("offset", [(0.0, 0.0), (0.1, -0.05)])
def test_a_perspective_camera_is_set_back_until_its_frame_holds_the_points(offset):
    """framing.perspective_fit: from the distance it gives, every point lies within
    1/MARGIN of the frame's half width or height (a lens shift moves the frame's centre
    off the axis), and the outermost point on that line; nearer, one would not."""
    from blobtree_ink.pipeline import framing as FR
    rng = np.random.default_rng(3)
    rel = rng.normal(size=(200, 3)) * [1.0, 2.0, 1.5]
    half = np.array([0.36, 0.2])
    t = FR.perspective_fit(rel, half, offset)
    image = np.abs(_project(rel, t, offset)) / half
    assert image.max() == pytest.approx(1 / FR.MARGIN)
    assert (np.abs(_project(rel, 0.98 * t, offset)) / half).max() > 1 / FR.MARGIN


def test_an_orthographic_camera_zooms_until_its_frame_holds_the_points():
    from blobtree_ink.pipeline import framing as FR
    rel = np.array([[1.0, 0.0, 5.0], [-0.5, 2.0, -3.0], [0.0, -1.0, 0.0]])
    zoom = FR.ortho_fit(rel, half=np.array([4.0, 2.0]))
    assert zoom == pytest.approx(FR.MARGIN * 1.0)                 # the point 2 up fills the half height 2
    assert (np.abs(rel[:, :2]) / (zoom * np.array([4.0, 2.0]))).max() == pytest.approx(1 / FR.MARGIN)


def test_stipples_keep_clear_of_the_outlines_whichever_request_draws_them(load_example):
    """No stipple touches a visible outline on the paper; Place Strokes alone, given the
    outlines drawn already (the ink's), draws the stipples a look (outlines and strokes
    in one run) draws, and traces nothing."""
    from blobtree_ink.strokes import stipples as SP
    model = load_example("pear")
    look = PL.Illustration(PL.Job(model, style=ST.style("stippled"),
                                  requests=(PL.Request("OUTLINES"), PL.Request("PLACE_STROKES"))))
    dots = look.run().strokes.layers["Stipples"]
    lines = [s for name in ("Silhouette", "Crease") for s in look.outline_set.layers[name]]
    alone = PL.Illustration(PL.Job(model, style=ST.style("stippled"), requests=(PL.Request("PLACE_STROKES"),),
                                   lines=tuple(lines)))
    res = alone.run()
    assert "Silhouette" not in res.owned and len(res.strokes.layers.get("Silhouette", ())) == 0
    assert res.progress.iterations == 0
    assert [d.mark for d in res.strokes.layers["Stipples"]] == [d.mark for d in dots]
    bare = PL.Illustration(PL.Job(model, style=ST.style("stippled"), requests=(PL.Request("PLACE_STROKES"),))).run()
    assert len(bare.strokes.layers["Stipples"]) > len(dots)          # without the lines, dots sit on them too
    U, a = SP.on_paper(np.concatenate([d.points for d in dots]), np.concatenate([d.radius for d in dots]), look.eye)
    for s in lines:                                  # each dot against the line's points, densified
        t = np.linspace(0.0, 1.0, 9)[:, None, None]
        P = (s.points[:-1][None] * (1 - t) + s.points[1:][None] * t).reshape(-1, 3)
        r = np.maximum(s.radius[:-1], s.radius[1:])[None].repeat(len(t), 0).reshape(-1)
        W, b = SP.on_paper(P, r, look.eye)
        i = ((U[:, None] - W[None]) ** 2).sum(-1).argmin(1)
        gap = np.linalg.norm(U - W[i], axis=1)
        assert np.all(gap >= 0.99 * (a + b[i])), s.points.shape
