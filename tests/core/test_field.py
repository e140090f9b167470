"""Field values against hand-computed values for every node type, gradients against
finite differences, pruned against naive evaluation, single point against batch."""
import math

import numpy as np
import pytest
from conftest import ALL_MODELS
from helpers import fd_gradient, near_surface_points

from blobtree_ink import model as M

K3 = 0.421875       # (1 - 1/4)^3: the kernel at d = R/2


def ev_of(root, iso=0.5):
    return M.Evaluator(M.from_dict({"format": "blobtree-1", "iso": iso, "root": root}))


def pt(c, R, s=None):
    d = {"type": "point", "center": list(c), "radius": R}
    if s is not None:
        d["strength"] = s
    return d


def f_at(root, pts, iso=0.5):
    return ev_of(root, iso).field(np.array(pts, float))


CASES = [
    (pt((0, 0, 0), 2, 1.5), [(1, 0, 0), (0, 0, 0), (2, 0, 0), (0, 3, 0)], [1.5 * 0.75 ** 3, 1.5, 0, 0]),
    ({"type": "segment", "a": [0, 0, 0], "b": [2, 0, 0], "radius": 1},
     [(1, 0.5, 0), (3, 0, 0), (-0.5, 0, 0), (2, 0, 0)], [K3, 0, K3, 1]),
    ({"type": "segment", "a": [1, 1, 1], "b": [1, 1, 1], "radius": 1}, [(1, 1, 1.5)], [K3]),
    ({"type": "circle", "center": [0, 0, 0], "normal": [0, 0, 2], "circle_radius": 1, "radius": 1},
     [(1, 0, 0.5), (0, 0, 0), (0, 1.5, 0), (-1, 0, 0)], [K3, 0, K3, 1]),
    ({"type": "circle", "center": [0, 0, 0], "normal": [1, 0, 0], "circle_radius": 1, "radius": 2},
     [(0, 0, 0), (0, 0, 1)], [K3, 1]),
    ({"type": "disc", "center": [0, 0, 0], "normal": [0, 0, 1], "disc_radius": 1, "radius": 1},
     [(0.5, 0, 0.5), (1.5, 0, 0), (0.3, 0.3, 0), (0, 0, 1)], [K3, K3, 1, 0]),
    ({"type": "box", "center": [1, 1, 1], "half_size": [1, 1, 1], "radius": 1},
     [(1, 1, 1), (2.5, 1, 1), (2.5, 2.5, 1), (0, 0, 0)], [1, K3, 0.5 ** 3, 1]),
    ({"type": "box", "center": [0, 0, 0], "half_size": [0, 0, 0], "radius": 1}, [(0.5, 0, 0)], [K3]),
    ({"type": "blend", "children": [pt((0, 0, 0), 2), pt((2, 0, 0), 2)]}, [(1, 0, 0)], [2 * 0.75 ** 3]),
    ({"type": "ricci", "n": 2, "children": [pt((0, 0, 0), 1, 0.6), pt((0, 0, 0), 1, 0.8)]},
     [(0, 0, 0), (0.5, 0, 0)], [1.0, K3]),
    ({"type": "ricci", "n": 1, "children": [pt((0, 0, 0), 1, 0.6), pt((0, 0, 0), 1, 0.8)]}, [(0, 0, 0)], [1.4]),
    ({"type": "union", "children": [pt((0, 0, 0), 1, 0.6), pt((0, 0, 0), 1, 0.8)]}, [(0, 0, 0)], [0.8]),
    ({"type": "intersection", "children": [pt((0, 0, 0), 1, 0.6), pt((0, 0, 0), 1, 0.8)]}, [(0, 0, 0)], [0.6]),
    ({"type": "intersection", "children": [pt((0, 0, 0), 1), pt((3, 0, 0), 1)]}, [(0, 0, 0)], [0]),
    # min(f0, 2 iso - f1) with iso 0.5: min(1, 1 - K3) and, far from f0, min(0, 1 - 1) = 0
    ({"type": "difference", "children": [pt((0, 0, 0), 2), pt((1, 0, 0), 2)]},
     [(0, 0, 0), (1, 0, 0)], [1 - K3, 0.0]),
    ({"type": "difference", "children": [pt((0, 0, 0), 1), pt((5, 0, 0), 1, 3.0), pt((5, 0, 0), 1)]},
     [(0, 0, 0), (5, 0, 0)], [1.0, -2.0]),
    ({"type": "transform", "translate": [1, 0, 0], "rotate": [0, 0, math.pi / 2], "scale": [2, 2, 2],
      "child": pt((1, 0, 0), 1)}, [(1, 2, 0), (1, 2, 1)], [1, K3]),
    ({"type": "transform", "scale": [2, 1, 1], "child": pt((0, 0, 0), 1)}, [(1, 0, 0), (0, 0.5, 0)], [K3, K3]),
    # Blender's XYZ Euler: X first, then Z
    ({"type": "transform", "rotate": [math.pi / 2, 0, math.pi / 2], "child": pt((0, 1, 0), 1)},
     [(0, 0, 1), (-1, 0, 0)], [1, 0]),
    ({"type": "twist", "rate": math.pi / 2, "child": {"type": "segment", "a": [1, 0, -1], "b": [1, 0, 1],
                                                      "radius": 0.5}}, [(0, 1, 1), (1, 0, 0)], [1, 1]),
    ({"type": "taper", "rate": 1, "child": pt((1, 0, 1), 0.5)}, [(2, 0, 1)], [1]),
    ({"type": "taper", "rate": -1, "child": pt((1, 0, 2), 0.5)}, [(0.05, 0, 2)], [1]),
    ({"type": "bend", "rate": 1, "child": pt((math.pi / 2, 0, 0), 0.5)}, [(1, 0, 1)], [1]),
    ({"type": "bend", "rate": -1, "child": pt((math.pi / 2, 0, 0), 0.5)}, [(1, 0, -1)], [1]),
    ({"type": "bend", "rate": 0, "child": pt((0, 0, 0), 2)}, [(1, 0, 0)], [0.75 ** 3]),
]


@pytest.mark.parametrize("root, pts, want", CASES, ids=[c[0]["type"] + str(i) for i, c in enumerate(CASES)])
@pytest.mark.parametrize("optimize", [True, False])
def test_hand_computed_values(root, pts, want, optimize):
    ev = M.Evaluator(M.from_dict({"format": "blobtree-1", "root": root}), optimize=optimize)
    np.testing.assert_allclose(ev.field(np.array(pts, float)), want, rtol=1e-12, atol=1e-12)


def test_lone_point_meets_iso_at_documented_radius():
    R = 1.7
    d = R * math.sqrt(1 - 0.5 ** (1 / 3))
    assert abs(f_at(pt((0, 0, 0), R), [(d, 0, 0)])[0] - 0.5) < 1e-12
    assert abs(d / R - 0.4543) < 1e-4


@pytest.mark.parametrize("i", range(len(CASES)))
def test_gradient_of_every_node_type_matches_finite_differences(i):
    root = CASES[i][0]
    ev = ev_of(root)
    rng = np.random.default_rng(i)
    lo, hi = ev.bounds
    if np.any(lo > hi):     # empty support (disjoint intersection): zero everywhere
        P = rng.uniform(-4, 4, size=(4000, 3))
        f, g = ev.field_grad(P)
        assert not f.any() and not g.any()
        return
    lo, hi = np.maximum(lo, -4), np.minimum(hi, 4)
    P = rng.uniform(lo, hi, size=(4000, 3))
    f, g = ev.field_grad(P)
    P, g = P[f > 1e-3], g[f > 1e-3]
    fd = fd_gradient(ev, P)
    err = np.linalg.norm(g - fd, axis=1) / np.maximum(np.linalg.norm(fd, axis=1), 1.0)
    # CSG switches and clamps are kinks: only a sliver of points may sit within h of one
    assert len(P) > 50
    assert np.mean(err < 1e-5) > 0.995, (root["type"], np.sort(err)[-5:])


@pytest.mark.parametrize("name", ALL_MODELS)
def test_gradient_matches_finite_differences_on_examples(name, load_example):
    ev = M.Evaluator(load_example(name))
    P = near_surface_points(ev, 1500, seed=1)
    f, g = ev.field_grad(P)
    fd = fd_gradient(ev, P)
    err = np.linalg.norm(g - fd, axis=1) / np.maximum(np.linalg.norm(fd, axis=1), 1.0)
    assert np.mean(err < 1e-5) > 0.99, np.sort(err)[-5:]
    np.testing.assert_allclose(f, ev.field(P), rtol=0, atol=0)


@pytest.mark.parametrize("name", ALL_MODELS)
def test_pruned_equals_naive_on_every_example(name, load_example):
    m = load_example(name)
    fast, naive = M.Evaluator(m), M.Evaluator(m, optimize=False)
    rng = np.random.default_rng(3)
    lo, hi = fast.bounds
    P = np.concatenate([near_surface_points(fast, 2000, seed=2),
                        rng.uniform(lo - 0.5, hi + 0.5, size=(1000, 3))])
    f1, g1 = fast.field_grad(P)
    f2, g2 = naive.field_grad(P)
    np.testing.assert_allclose(f1, f2, rtol=0, atol=1e-12)
    np.testing.assert_allclose(g1, g2, rtol=0, atol=1e-10 * max(1.0, np.abs(g2).max()))
    np.testing.assert_allclose(fast.field(P), f1, rtol=0, atol=0)
    if name in ("shell", "train", "heart"):
        assert fast.stats.primitives_per_point < 0.1 * naive.stats.primitives_per_point


def test_single_point_is_a_batch_of_one(load_example):
    ev = M.Evaluator(load_example("pear"))
    P = near_surface_points(ev, 20, seed=5)
    batch = ev.field_grad(P)
    for i, p in enumerate(P):
        f, g = ev.field_grad(p)
        assert f.shape == (1,) and g.shape == (1, 3)
        assert f[0] == batch[0][i] and np.array_equal(g[0], batch[1][i])
    with pytest.raises(ValueError, match=r"\(N,3\)"):
        ev.field(np.zeros((4, 2)))


def test_support_bounds_are_conservative(load_example):
    for name in ("jug", "train", "shell"):
        ev = M.Evaluator(load_example(name))
        lo, hi = ev.bounds
        rng = np.random.default_rng(0)
        span = hi - lo
        P = rng.uniform(lo - span, hi + span, size=(20000, 3))
        outside = ~np.all((P >= lo) & (P <= hi), axis=1)
        naive = M.Evaluator(load_example(name), optimize=False)
        assert np.all(naive.field(P[outside]) == 0)


def _holed(x, y=0.0, strong=3.0):
    """A disc-like blob with a strong subtracted point: negative near the hole."""
    return {"type": "difference", "children": [pt((x, y, 0), 1.0), pt((x + 0.3, y, 0), 0.8, strong)]}


@pytest.mark.parametrize("op", ["union", "blend"])
def test_identical_subtrees_are_stacked_and_equal_the_naive_evaluation(op):
    # five identical differences (two overlapping) and nothing else, so that the stack
    # alone decides: the members are negative around their holes, where a union must
    # still give 0 for a point that other members' boxes miss (they are 0 there)
    kids = [_holed(x) for x in (0.0, 3.0, 6.0, 9.0, 9.5)]
    root = {"type": op, "children": kids}
    fast = ev_of(root)
    naive = M.Evaluator(M.from_dict({"format": "blobtree-1", "root": root}), optimize=False)
    from blobtree_ink.model.stack import Stack
    stacks = [c for c in fast.plan.children if isinstance(c, Stack)]
    assert len(stacks) == 1 and stacks[0].K == 5
    rng = np.random.default_rng(7)
    P = np.concatenate([rng.uniform((-1.5, -1.5, -1.2), (11, 4.5, 1.2), size=(4000, 3)),
                        [[0.3, 0, 0], [9.3, 0, 0], [9.8, 0, 0], [20, 0, 0]]])
    f1, g1 = fast.field_grad(P)
    f2, g2 = naive.field_grad(P)
    np.testing.assert_allclose(f1, f2, rtol=0, atol=1e-12)
    np.testing.assert_allclose(g1, g2, rtol=0, atol=1e-10)
    assert (f2 > 0.5).any()
    hole = np.flatnonzero(ev_of(_holed(0.0)).field(P) < 0)  # where a member is negative
    assert len(hole) > 10
    if op == "union":
        assert np.all(f1[hole] >= 0) and (f1[hole] == 0).any()
    else:
        assert (f1[hole] < 0).any()
    np.testing.assert_array_equal(fast.field(P), f1)
    for i in (0, 100, 4001, 4002):                         # one point is a batch of one
        f, g = fast.field_grad(P[i])
        assert f[0] == f1[i] and np.array_equal(g[0], g1[i])


def _mixed_blend(x):
    """A blend of 17 primitives in groups too small for a grid (4 points, 4 segments,
    4 boxes, 4 discs and a circle): every one is evaluated on every point."""
    kids = []
    for j in range(4):
        c = (x + 0.1 * j, 0.2 * j, 0.0)
        kids += [pt(c, 0.5),
                 {"type": "segment", "a": list(c), "b": [c[0] + 0.3, c[1], 0.1], "radius": 0.4},
                 {"type": "box", "center": [c[0], c[1], 0.3], "half_size": [0.1, 0.1, 0.1], "radius": 0.3},
                 {"type": "disc", "center": [c[0], c[1], -0.3], "normal": [0, 0, 1], "disc_radius": 0.2,
                  "radius": 0.3}]
    kids.append({"type": "circle", "center": [x, 0, 0], "normal": [0, 1, 0], "circle_radius": 0.5, "radius": 0.3})
    return {"type": "blend", "children": kids}


def test_few_or_large_identical_subtrees_are_not_stacked():
    from blobtree_ink.model.stack import STACK_MAX_PRIMS, Stack
    two = ev_of({"type": "union", "children": [_holed(0.0), _holed(3.0)]})
    assert not any(isinstance(c, Stack) for c in two.plan.children)
    # a stack evaluates every primitive of a small group on each of a member's points
    assert 17 > STACK_MAX_PRIMS
    big = ev_of({"type": "union", "children": [_mixed_blend(x) for x in (0.0, 3.0, 6.0)]})
    assert [len(c.children) for c in big.plan.children] == [5, 5, 5]
    assert not any(isinstance(c, Stack) for c in big.plan.children)


def test_identical_subtrees_with_large_groups_are_stacked_and_those_keep_a_grid():
    # each member subtracts 40 points: one gridded group, which meets only the few near
    # a point, so the members stack; the stacked group's grid gives the values of every
    # member's primitives evaluated on every point
    from blobtree_ink.model import groups as G
    from blobtree_ink.model.stack import Stack
    holes = [{"type": "difference", "children": [pt((x, 0, 0), 1.2)] +
              [pt((x + 0.8 * np.cos(a), 0.8 * np.sin(a), 0), 0.25, 2.0) for a in np.linspace(0, 6, 40)]}
             for x in (0.0, 2.0, 4.0, 6.5)]
    root = {"type": "union", "children": holes}
    fast = ev_of(root)
    stacks = [c for c in fast.plan.children if isinstance(c, Stack)]
    assert len(stacks) == 1 and stacks[0].K == 4
    sub = stacks[0].shape.children[1]
    assert sub.m == 40 and sub.grid is not None
    naive = M.Evaluator(M.from_dict({"format": "blobtree-1", "iso": 0.5, "root": root}), optimize=False)
    P = np.random.default_rng(5).uniform((-1.5, -1.5, -0.5), (8, 1.5, 0.5), size=(3000, 3))
    assert len(P) * sub.m > G.SMALL_DENSE                 # the grid, not every member on every point
    f1, g1 = fast.field_grad(P)
    f2, g2 = naive.field_grad(P)
    np.testing.assert_allclose(f1, f2, rtol=0, atol=1e-12)
    np.testing.assert_allclose(g1, g2, rtol=0, atol=1e-10)
    assert (f2 > 0.5).any() and (f2 < 0.5).any()
    kk = np.zeros(len(P), np.int64)
    pp, pi, counts = sub.pairs(P.T.copy(), kk)
    assert len(pp) < len(P) * sub.m / 4 and np.all(pi < sub.m)
    assert np.all(np.diff(pp) >= 0) and np.all(np.diff(pi)[np.diff(pp) == 0] > 0)
    for i in (0, 17, 2999):                               # one point is a batch of one
        f, g = fast.field_grad(P[i])
        assert f[0] == f1[i] and np.array_equal(g[0], g1[i])


def test_a_stack_of_many_members_tests_its_boxes_in_blocks(monkeypatch):
    # thousands of identical subtrees must not need a (points x members) array at once
    from blobtree_ink.model import stack as ST
    kids = [_holed(3.0 * (i % 20), 3.0 * (i // 20)) for i in range(60)]
    root = {"type": "union", "children": kids}
    fast = ev_of(root)
    assert [c.K for c in fast.plan.children if isinstance(c, ST.Stack)] == [60]
    naive = M.Evaluator(M.from_dict({"format": "blobtree-1", "root": root}), optimize=False)
    P = np.random.default_rng(2).uniform((-1.5, -1.5, -1), (59, 8, 1), size=(3000, 3))
    whole = fast.field_grad(P)
    monkeypatch.setattr(ST, "PAIR_BLOCK", 600)            # blocks of 10 points
    blocked = fast.field_grad(P)
    np.testing.assert_array_equal(blocked[0], whole[0])
    np.testing.assert_array_equal(blocked[1], whole[1])
    np.testing.assert_allclose(blocked[0], naive.field(P), rtol=0, atol=1e-12)


def test_a_stack_of_many_members_finds_the_boxes_of_a_large_batch_in_a_grid(monkeypatch):
    # the grid's candidates, tested against the boxes, are exactly the dense test's
    # pairs in the same order (by point, then member), for points inside, outside and
    # on the faces of the members' boxes
    from blobtree_ink.model import stack as ST
    kids = [_holed(3.0 * (i % 20), 3.0 * (i // 20)) for i in range(60)]
    fast = ev_of({"type": "union", "children": kids})
    stack = next(c for c in fast.plan.children if isinstance(c, ST.Stack))
    assert stack.grid is not None and stack.grid["dims"].prod() > 1
    rng = np.random.default_rng(3)
    P = np.concatenate([rng.uniform(stack.lo - 1, stack.hi + 1, size=(3000, 3)), stack.member_lo, stack.member_hi,
                        [stack.lo, stack.hi, stack.lo - 5]]).T.copy()
    assert P.shape[1] * stack.K >= ST.GRID_MIN_PAIRS
    pp, kk = stack.pairs(P)
    monkeypatch.setattr(ST, "GRID_MIN_PAIRS", 1 << 62)          # every box on every point
    dp, dk = stack.pairs(P)
    np.testing.assert_array_equal(pp, dp)
    np.testing.assert_array_equal(kk, dk)
    on_face = np.arange(3000, 3000 + 2 * stack.K)
    assert np.isin(on_face, pp).all() and len(pp) > 3000 * 0.2
    # each member's two corners are in its own box
    for k in range(stack.K):
        assert k in kk[pp == 3000 + k] and k in kk[pp == 3000 + stack.K + k]
