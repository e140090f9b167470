"""Drawing styles: strokes from feature chains, short strokes on polygon centres,
flocks, convex/concave regions, flow fields, tone from the light, batched hidden-line
removal, and the style's validation."""
import dataclasses
import math

import numpy as np
import pytest

from blobtree_ink import model as M
from blobtree_ink import pipeline as PL
from blobtree_ink.agents import Session, Settings
from blobtree_ink.blackboard.view import View
from blobtree_ink.model.curvature import curvature
from blobtree_ink.agents import steering as st
from blobtree_ink.strokes import layers, smarticles as sm, style as ST
from blobtree_ink.strokes.visibility import split_visible, split_visible_many

K = math.sqrt(1 - 0.5 ** (1 / 3))      # sphere radius of an R=1 primitive at iso 0.5


def ev_of(root):
    return M.Evaluator(M.from_dict({"format": "blobtree-1", "root": root}))


def drawn(ev, eye, light, style, seed=0, res=14, outlines=True):
    """The strokes of an illustration through the pipeline (outlines and the style's
    strokes; lines of radius 0.01)."""
    requests = ((PL.Request("OUTLINES"),) if outlines else ()) + (PL.Request("PLACE_STROKES"),)
    style = dataclasses.replace(style, line_width=0.01 / PL.line_radius(ev))
    job = PL.Job(ev, View(eye=eye), light, style, requests, seed, Settings(resolution=res, seed=1))
    return PL.Illustration(job).run().strokes


@pytest.fixture(scope="module")
def sphere_session():
    ev = ev_of({"type": "point", "center": [0, 0, 0], "radius": 1.0})
    eye = np.array([0.0, -4.0, 0.0])
    s = Session(ev, View(eye=eye), Settings(resolution=14, seed=1))
    s.request("OUTLINES")
    s.run()
    return s, eye


@pytest.fixture(scope="module")
def blend_session(load_example):
    ev = M.Evaluator(load_example("csg_difference"))      # the bite is a concave spherical cap
    eye = np.array([4.0, -1.5, 0.6])
    s = Session(ev, View(eye=eye), Settings(resolution=16, seed=1))
    s.request("OUTLINES")
    s.run()
    return s, eye


def test_default_light_comes_from_the_viewers_upper_left():
    centre, eye = np.zeros(3), np.array([0.0, -5.0, 0.0])       # looking along +y: the viewer's right is +x
    L = PL.default_light(centre, eye)
    assert abs(np.linalg.norm(L) - 1) < 1e-12
    assert L[0] < -0.3 and L[2] > 0.3 and L[1] < 0        # left, up, towards the viewer


def test_outlines_are_heavier_on_the_side_turned_from_the_light_and_contrast_zero_is_uniform():
    N = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 0.0, -1.0]])
    r = ST.heavier(N, (0.0, 0.0, 1.0), 2.0, 1.0)
    assert r[0] == pytest.approx(1.5) and r[1] == pytest.approx(2.5) and r[2] == pytest.approx(2.5)
    assert np.all(ST.heavier(N, (0.0, 0.0, 1.0), 2.0, 0.0) == 2.0)


def test_contour_field_is_tangent_and_across_the_view(sphere_session):
    s, eye = sphere_session
    P = s.mesh.vertices[:200]
    N = s.vertex_normals[:200]
    d = layers.direction_field("contour", eye=eye)(P, N, {})
    view = st.unit(eye - P)
    assert np.abs(np.einsum("ij,ij->i", d, N)).max() < 1e-9
    assert np.abs(np.einsum("ij,ij->i", d, view)).max() < 1e-9
    with pytest.raises(ValueError, match="contour flow field needs the eye"):
        layers.direction_field("contour")
    with pytest.raises(ValueError, match="unknown flow field 'spiral'"):
        layers.direction_field("spiral")


def test_the_diagonal_field_is_half_way_between_the_principal_directions():
    """On a segment (a tube with distinct principal curvatures) the diagonal field is a
    unit tangent 45 degrees from each principal direction, dir1 turned towards dir2; a
    mark's heading along it follows its reference direction's way."""
    ev = ev_of({"type": "segment", "a": [-2, 0, 0], "b": [2, 0, 0], "radius": 1.0})
    t = np.linspace(0.3, 2.8, 12)
    P = np.stack([np.linspace(-0.8, 0.8, 12), K * np.cos(t), K * np.sin(t)], axis=1)
    _, g = ev.field_grad(P)
    c = curvature(ev, P, g)
    d = layers.direction_field("diagonal")(P, c["normal"], {**c, "velocity": np.zeros_like(P)})
    assert np.allclose(np.linalg.norm(d, axis=1), 1.0)
    assert np.abs(np.einsum("ij,ij->i", d, c["normal"])).max() < 1e-9
    assert np.allclose(np.einsum("ij,ij->i", d, c["dir1"]), math.sqrt(0.5))
    assert np.allclose(np.einsum("ij,ij->i", d, c["dir2"]), math.sqrt(0.5))
    assert np.allclose(np.abs(d[:, 0]), math.sqrt(0.5), atol=1e-6)       # the tube's axis and its rings
    ref = -d + 0.1 * c["normal"]
    H = layers.headings(ev, P, "diagonal", ref)
    assert np.allclose(H, -d, atol=1e-9)


def test_feature_distance_ends_a_stroke_without_its_terminating_point():
    ev = ev_of({"type": "point", "center": [0, 0, 0], "radius": 1.0})
    feat = np.array([[K * math.cos(t), K * math.sin(t), 0.0] for t in np.linspace(0, 2 * math.pi, 400)])
    start = np.array([[K, 0.0, 0.0]])
    rules = sm.StrokeRules(max_steps=100, max_normal_angle=math.pi, stop_on_curvature_sign=False,
                           feature_points=feat, max_feature_distance=0.2)
    res = sm.run(ev, start, layers.direction_field("axis", (0, 0, 1)), 0.02, sm.PRESETS["hatching"], rules,
                 np.zeros(1, np.uint64))
    assert res.reasons[0] == "feature distance"
    d = sm.nearest_distance(res.paths[0], feat)
    assert d.max() <= 0.2 and d.max() > 0.2 - 0.03          # went as far as allowed, not a step further
    assert np.allclose(sm.nearest_distance(np.eye(3), np.eye(3)[:2]), [0, 0, math.sqrt(2)])


def test_chain_seeds_start_on_the_silhouette_and_head_to_its_visible_side(sphere_session):
    s, eye = sphere_session
    sil = [o for o in s.outlines() if o.kind == "silhouette"]
    P, N, H = layers.chain_seeds(sil, eye, every=1, angle=90.0)
    sparse, _, _ = layers.chain_seeds(sil, eye, every=4, angle=90.0)
    assert len(P) > 20 and 3 < len(P) / len(sparse) < 5          # the density step indexes every n-th chain point
    assert np.allclose(np.einsum("ij,ij->i", H, N), 0, atol=1e-6)   # along the surface
    assert (np.einsum("ij,ij->i", H, eye - P) > 0).all()         # into the visible side
    with pytest.raises(ValueError, match="chain density step must be at least 1"):
        layers.chain_seeds(sil, eye, every=0)


def test_chain_strokes_start_at_the_silhouette_and_keep_to_the_shade(sphere_session):
    """Silhouette shading: lines from the silhouette into its visible side, on the
    surface, in the shade (the lit half has none) and no longer than the chain distance."""
    s, eye = sphere_session
    light = np.array([1.0, 0.0, 0.0])          # the -x half is in shade
    out = drawn(s.ev, eye, light, ST.style("silhouette-shading"))
    strokes = out.layers["Chains"]
    assert len(strokes) > 10
    P = np.concatenate([x.points for x in strokes])
    assert np.abs(s.ev.field(P) - 0.5).max() < 1e-6
    assert (P[:, 0] < 0.7 * K).all()                                     # (the highlight threshold: 0.7 of the light)
    sil = np.concatenate([o.points for o in s.outlines() if o.kind == "silhouette"])
    starts = np.array([x.points[0] for x in strokes])
    assert (sm.nearest_distance(starts, sil) < 0.05 * K).sum() > 10        # (the others fill in beside them)


def test_short_strokes_are_short_and_tone_the_shade(sphere_session):
    s, eye = sphere_session
    light = np.array([0.0, 0.0, 1.0])
    out = drawn(s.ev, eye, light, ST.style("outlines", short=True, outlines=False), outlines=False)
    strokes = out.layers["Short Strokes"]
    assert len(strokes) > 20
    assert max(len(x.points) for x in strokes) <= 2 * PL.layers.SHORT_STEPS + 1
    P = np.concatenate([x.points for x in strokes])
    assert np.abs(s.ev.field(P) - 0.5).max() < 1e-6 and (P[:, 2] < 0.7 * K).all()


def test_concave_hatching_stays_in_the_concave_region(blend_session):
    s, eye = blend_session
    assert (s.vertex_curvature["mean"] < 0).any()
    light = np.array([0.0, 0.0, 1.0])
    st_ = ST.style("outlines", hatching=True, cross_hatching=False, surface="concave", outlines=False,
                   shade_lower=0.99, shade_upper=1.0)
    out = drawn(s.ev, eye, light, st_, res=16, outlines=False)
    assert out.count("Silhouette") == 0
    strokes = out.layers["Hatching"]
    assert len(strokes) > 3
    P = np.concatenate([x.points for x in strokes])
    assert curvature(s.ev, P)["mean"].max() < 0
    convex = drawn(s.ev, eye, light, dataclasses.replace(st_, surface="convex"), res=16, outlines=False)
    P = np.concatenate([x.points for x in convex.layers["Hatching"]])
    assert curvature(s.ev, P)["mean"].min() > 0


def test_flocks_spawn_side_by_side_and_flocked_hatching_differs(blend_session):
    starts = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0]])
    normals = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0]])
    heads = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    P, H, ids, members = layers.spawn_flocks(starts, normals, heads, 5, 0.1, np.array([7, 9], np.uint64))
    assert P.shape == (10, 3) and list(ids) == [0] * 5 + [1] * 5 and len(set(members.tolist())) == 10
    assert np.allclose(H[:5], heads[0]) and np.allclose(H[5:], heads[1])
    assert np.ptp(P[:5, 1]) > 0.3 and np.ptp(P[5:, 2]) > 0.3      # spread across the heading
    # a flock spawned about a turned start is the same flock, turned (its places are its keys')
    R = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    Q, _, _, _ = layers.spawn_flocks(starts @ R.T, normals @ R.T, heads @ R.T, 5, 0.1, np.array([7, 9], np.uint64))
    assert np.allclose(Q, P @ R.T, atol=1e-12)
    s, eye = blend_session
    light = np.array([0.0, 0.0, 1.0])
    flock = drawn(s.ev, eye, light, ST.style("flocked"), res=16).layers["Hatching"]
    plain = drawn(s.ev, eye, light, ST.style("hatched", cross_hatching=False), res=16).layers["Hatching"]
    assert len(flock) > 5 and len(plain) > 5
    assert len(flock) != len(plain) or any(not np.array_equal(x.points, y.points) for x, y in zip(flock, plain))
    for x in flock:
        assert np.abs(s.ev.field(x.points) - 0.5).max() < 1e-6


def test_an_illustration_is_deterministic_and_tones_every_layer(sphere_session):
    s, eye = sphere_session
    light = PL.default_light(np.zeros(3), eye)
    st_ = ST.style("short-strokes", hatching=True, chains=True)
    a = drawn(s.ev, eye, light, st_, seed=5)
    b = drawn(s.ev, eye, light, st_, seed=5)
    for name in ("Silhouette", "Hatching", "Chains", "Stipples", "Short Strokes"):
        assert a.count(name) > 0 and a.count(name) == b.count(name)
        assert all(np.array_equal(x.points, y.points) for x, y in zip(a.layers[name], b.layers[name]))
    r = np.concatenate([x.radius for x in a.layers["Hatching"]])
    assert r.min() < 0.7 * r.max()                   # a light tone's lines are thinner
    sil = np.concatenate([x.radius for x in a.layers["Silhouette"]])
    assert sil.min() < sil.max()                      # heavier on the side turned from the light


def test_batched_visibility_equals_one_stroke_at_a_time():
    ev = ev_of({"type": "union", "children": [
        {"type": "point", "center": [0, 0, 0], "radius": 1.0},
        {"type": "point", "center": [0, 3, 0], "radius": 1.0}]})
    eye = np.array([0.0, -6.0, 0.0])
    x = np.linspace(-1.0, 1.0, 60)
    polys = [np.stack([x, 3 + dy + 0 * x, 0.5 * dy + 0 * x], 1) for dy in (-0.3, 0.0, 0.3)]
    polys.append(np.array([[2.0, 0.0, 0.0]]))
    one = [[r[:4] for r in split_visible(ev, p, eye)] for p in polys]
    many = [[r[:4] for r in rs] for rs in split_visible_many(ev, polys, eye)]
    assert one == many
    for r, dy in zip(many[:3], (-0.3, 0.0, 0.3)):     # the middle of each line is behind the front sphere
        W = (9 + dy) * K / math.sqrt(36 - K * K)              # the sphere's shadow cone at the line's depth
        w = math.sqrt(W * W - (0.5 * dy) ** 2)
        assert len(r) == 2 and r[0][0] == 0 and r[1][1] == 60
        assert abs(x[r[0][1]] + w) < 0.05 and abs(x[r[1][0] - 1] - w) < 0.05
    assert many[3] == []        # too short to be a stroke


def test_an_outline_that_would_draw_as_a_dot_is_left_out():
    """Whole outlines that fit in a box under DOT line widths (a tiny contour loop, a
    scrap) are not drawn; longer ones are, and what counts as a dot follows the line's
    width."""
    from blobtree_ink.agents.outline import Outline
    ev = ev_of({"type": "point", "center": [0, 0, 0], "radius": 1.0})
    d = 4.0
    eye = np.array([0.0, -d, 0.0])
    rim = K * math.sqrt(1 - (K / d) ** 2)                   # the silhouette circle, at y = -K^2 / d

    def arc(length):
        a = np.linspace(0.0, length / rim, 8)
        P = np.stack([rim * np.cos(a), np.full_like(a, -K * K / d), rim * np.sin(a)], 1)
        return Outline("silhouette", P, P / np.linalg.norm(P, axis=1)[:, None], False, 0.01)

    short, long_ = arc(0.05), arc(0.3)
    assert ST.is_dot(short.points, 0.01) and not ST.is_dot(short.points, 0.005)
    assert not ST.is_dot(long_.points, 0.01)
    for radius, drawn_arcs in ((0.01, [long_]), (0.005, [short, long_])):
        got = ST.outline_strokes([short, long_], ev, eye, radius).layers["Silhouette"]
        assert [len(s.points) for s in got] == [8] * len(drawn_arcs)
        for s, o in zip(got, drawn_arcs):
            assert np.allclose(np.sort(s.points, axis=0), np.sort(o.points, axis=0))


@pytest.mark.parametrize("change, message", [
    (dict(hatch_field="spiral"), "hatch_field must be one of"),
    (dict(surface="flat"), "surface must be one of all, convex, concave"),
    (dict(line_width=float("nan")), "line_width must be a number from 0.01 to 100"),
    (dict(contrast=2.0), "contrast must be a number from 0 to 1"),
    (dict(flock_size=0), "flock_size must be a whole number from 1 to 64"),
    (dict(chain_step=2.5), "chain_step must be a whole number"),
    (dict(weights="wobbly"), "weights preset must be one of hatching, flock, sketchy, stipple"),
    (dict(weights={"gravity": 1.0}), "unknown behaviour 'gravity'"),
    (dict(weights={"flow": float("inf")}), "weight flow must be a number from 0 to 100"),
    (dict(hatch_axis=(0, 0, 0)), "hatch_axis must be three finite numbers, not all zero"),
    (dict(shade_lower=0.8, shade_upper=0.2), r"shade_lower \(0.8\) must be below shade_upper \(0.2\)"),
    (dict(colour="red"), "unknown style setting 'colour'"),
])
def test_bad_styles_are_named(change, message):
    with pytest.raises(ValueError, match=message):
        ST.style("outlines", **change)
    with pytest.raises(ValueError, match="unknown style 'baroque'"):
        ST.style("baroque")


def test_a_loop_seen_in_part_is_one_stroke_across_its_start():
    """A ball's silhouette whose lower part a ball in front hides: the part that shows
    runs through the loop's start (its topmost point) and is drawn as one stroke, from
    one edge of the ball in front to the other, not as two meeting at the top."""
    from blobtree_ink.agents import Outline
    ev = ev_of({"type": "union", "children": [
        {"type": "point", "center": [0, 0, 0], "radius": 1.0},
        {"type": "point", "center": [0, -5.0, -0.5], "radius": 1.0}]})
    eye = np.array([0.0, -10.0, 0.0])
    from blobtree_ink.model.projection import project
    r = float(project(ev, np.array([[0.0, 0.0, 0.6]]), 30)[0][0, 2])       # the back ball's radius at iso
    t = np.linspace(0.0, 2 * np.pi, 80, endpoint=False)
    c, rho = np.array([0.0, -r * r / 10.0, 0.0]), r * math.sqrt(1.0 - r * r / 100.0)
    X = c + rho * np.stack([np.cos(t), np.zeros_like(t), np.sin(t)], axis=1)
    out = ST.outline_strokes([Outline("silhouette", X, X / r, True, 0.05)], ev, eye, 0.01)
    (stroke,) = out.layers["Silhouette"]
    assert not stroke.cyclic and stroke.points[:, 2].max() > 0.99 * rho          # over the top
    assert np.all(np.linalg.norm(np.diff(stroke.points, axis=0), axis=1) < 0.1)   # no jump across the start
    ends = stroke.points[[0, -1]]
    assert np.all(ends[:, 2] < 0.0) and abs(ends[0, 2] - ends[1, 2]) < 0.01       # both ends at the front ball's edge


def test_cross_hatching_along_the_hatchings_own_field_is_said():
    """A style whose cross-hatching follows the hatching's own flow field draws one
    direction twice: the run says so; the presets do not."""
    model = M.from_dict({"format": "blobtree-1", "root": {"type": "point", "center": [0, 0, 0], "radius": 1.0}})
    req = (PL.Request("PLACE_STROKES"),)
    same = PL.Illustration(PL.Job(model, style=ST.style("hatched", hatch_field="diagonal"), requests=req))
    assert any("Cross Field is the Flow Field" in w for w in same.warnings)
    straight = PL.Illustration(PL.Job(model, style=ST.style("hatched", hatch_field="straight", cross_field="straight"),
                                      requests=req))
    assert not any("Cross Field" in w for w in straight.warnings)          # each stroke keeps its own way
    for name in ST.STYLES:
        assert not any("Cross Field" in w for w in PL.Illustration(PL.Job(model, style=ST.style(name),
                                                                          requests=req)).warnings), name
