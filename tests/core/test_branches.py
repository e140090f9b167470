"""Branch records and pinned evaluation (model.branches): recording changes nothing,
a point's own pins give its own field, and another side's pins continue that side's
field across a crease (unions, differences, union groups and stacks)."""
import numpy as np
import pytest

from blobtree_ink import model as M
from blobtree_ink.model.branches import NOT_REACHED, ZERO

from conftest import ALL_MODELS
from test_field import _holed, ev_of, pt


def kernel(P, c, R, s=1.0):
    d2 = np.sum((P - np.asarray(c)) ** 2, axis=1)
    return np.where(d2 < R * R, s * (1 - d2 / (R * R)) ** 3, 0.0)


@pytest.mark.parametrize("name", ALL_MODELS)
def test_recording_changes_nothing_and_own_pins_give_the_own_field(name, load_example):
    ev = M.Evaluator(load_example(name))
    lo, hi = ev.bounds
    P = lo + (hi - lo) * np.random.default_rng(3).random((3000, 3))
    f, g = ev.field_grad(P)
    f1, g1, table = ev.record(P)
    assert table.shape == (len(P), ev.sites.count) and table.dtype == np.int32
    assert np.array_equal(f, f1) and np.array_equal(g, g1)
    f2, g2 = ev.pinned(P, table)
    assert np.array_equal(f, f2) and np.array_equal(g, g2)
    if name in ("csg_union", "csg_difference", "pear", "jug", "train", "shell"):
        assert ev.sites.count > 0 and (table >= ZERO).any()
    if name == "train":
        # its wheels are a stack: sites inside the shared shape have a column per wheel
        assert ev.sites.count > 50


def test_a_union_groups_pins_continue_one_sphere_across_the_crease():
    c0, c1, R = (0.0, 0, 0), (0.8, 0, 0), 1.5
    ev = ev_of({"type": "union", "children": [pt(c0, R), pt(c1, R)]})
    assert ev.sites.count == 1                         # one union group of two points
    _, _, rec = ev.record([[-1.0, 0, 0], [1.8, 0, 0]])
    assert rec[:, 0].tolist() == [0, 1]                # each side's nearer sphere
    Q = np.array([[1.2, 0.1, 0], [1.5, -0.2, 0.1], [0.4, 0.5, 0], [-0.9, 0, 0.3]])
    for row, c in ((0, c0), (1, c1)):
        f, g = ev.pinned(Q, np.repeat(rec[row:row + 1], len(Q), axis=0))
        np.testing.assert_allclose(f, kernel(Q, c, R), rtol=0, atol=1e-15)
    # a point beyond the pinned sphere's reach: that sphere's field there, 0
    f, g = ev.pinned([[2.0, 0, 0]], rec[:1])
    assert f[0] == 0.0 and not g.any()


def test_a_difference_pins_the_subtracted_sheet_and_the_body_apart():
    body, hole = pt((0, 0, 0), 1.5), pt((0.9, 0, 0), 1.0, 2.0)
    ev = ev_of({"type": "difference", "children": [body, hole]})
    iso = ev.iso
    _, _, rec = ev.record([[-0.8, 0, 0], [0.55, 0, 0]])       # on the body, in the bite
    assert rec[0, 0] == 0 and rec[1, 0] == 1
    Q = np.array([[0.4, 0.1, 0], [-0.5, 0.2, 0.1], [0.7, -0.1, 0]])
    fb, _ = ev.pinned(Q, np.repeat(rec[:1], len(Q), axis=0))
    np.testing.assert_allclose(fb, kernel(Q, (0, 0, 0), 1.5), atol=1e-15)
    fh, _ = ev.pinned(Q, np.repeat(rec[1:], len(Q), axis=0))
    np.testing.assert_allclose(fh, 2 * iso - kernel(Q, (0.9, 0, 0), 1.0, 2.0), atol=1e-15)


def test_a_union_operators_pins_choose_between_unlike_children():
    seg = {"type": "segment", "a": [0.5, -1, 0], "b": [0.5, 1, 0], "radius": 0.8}
    ev = ev_of({"type": "union", "children": [pt((0, 0, 0), 1.5), seg]})
    _, _, rec = ev.record([[-1.0, 0, 0], [0.5, 0.9, 0]])
    assert rec[0].tolist() != rec[1].tolist()
    Q = np.array([[0.5, 0.6, 0.1], [-0.6, 0.0, 0.0]])
    f, _ = ev.pinned(Q, np.repeat(rec[:1], 2, axis=0))
    np.testing.assert_allclose(f, kernel(Q, (0, 0, 0), 1.5), atol=1e-15)
    alone = ev_of(seg)
    f, _ = ev.pinned(Q, np.repeat(rec[1:], 2, axis=0))
    np.testing.assert_allclose(f, alone.field(Q), atol=1e-15)


def test_a_stacks_pins_follow_one_member_across_its_neighbours():
    kids = [_holed(x) for x in (0.0, 1.5, 3.0, 4.5)]            # overlapping identical discs
    ev = ev_of({"type": "union", "children": kids})
    from blobtree_ink.model.stack import Stack
    assert any(isinstance(c, Stack) for c in ev.plan.children)
    _, _, rec = ev.record([[-0.6, 0, 0]])                        # only the first disc here
    Q = np.array([[0.75, 0.2, 0], [0.9, -0.1, 0.05], [1.6, 0, 0], [6.0, 0, 0]])
    f, g = ev.pinned(Q, np.repeat(rec, len(Q), axis=0))
    f0, g0 = ev_of(_holed(0.0)).field_grad(Q)
    np.testing.assert_allclose(f, f0, atol=1e-15)
    np.testing.assert_allclose(g, g0, atol=1e-13)
    plain = ev.field(Q)
    assert (np.abs(plain - f) > 1e-3).any()                      # the neighbours do win there


def test_pins_of_the_wrong_shape_are_named():
    ev = ev_of({"type": "union", "children": [pt((0, 0, 0), 1.5), pt((0.8, 0, 0), 1.5)]})
    with pytest.raises(ValueError, match=r"pins must be an \(2, 1\) table, got \(1, 1\)"):
        ev.pinned(np.zeros((2, 3)), np.full((1, 1), NOT_REACHED))


def test_a_record_longer_than_one_evaluation_chunk_keeps_every_points_row(monkeypatch):
    from blobtree_ink.model import evaluate as E
    monkeypatch.setattr(E, "CHUNK", 64)                 # 1000 points: 16 chunks
    ev = ev_of({"type": "union", "children": [pt((0, 0, 0), 1.5), pt((0.8, 0, 0), 1.5)]})
    x = np.linspace(-1.4, 2.2, 1000)
    P = np.stack([x, 0.1 * np.ones_like(x), np.zeros_like(x)], axis=1)
    f, g, rec = ev.record(P)
    near = np.where(np.abs(P[:, 0]) < np.abs(P[:, 0] - 0.8), 0, 1)
    inside = np.minimum(np.abs(P[:, 0]), np.abs(P[:, 0] - 0.8)) < 1.4
    assert np.array_equal(rec[inside, 0], near[inside])
    # every point pinned to the first sphere, across all chunks
    fp, _ = ev.pinned(P, np.zeros((1000, 1), np.int32))
    np.testing.assert_allclose(fp, kernel(P, (0, 0, 0), 1.5), atol=1e-15)


def test_a_union_of_many_unlike_subtrees_records_and_pins_each_child():
    # twelve differences, the i-th with i + 1 bites (twelve shapes: no stack), so one
    # union site chooses among twelve subtrees
    kids = [{"type": "difference", "children": [pt((1.1 * i, 0, 0), 1.0)] +
             [pt((1.1 * i + 0.5, 0.4, 0.05 * j), 0.5, 2.0) for j in range(i + 1)]} for i in range(12)]
    ev = ev_of({"type": "union", "children": kids})
    assert len(ev.plan.children) == 12
    P = np.random.default_rng(5).uniform((-1, -1, -0.5), (13, 1, 0.5), size=(5000, 3))
    f, g = ev.field_grad(P)
    f1, g1, rec = ev.record(P)
    assert np.array_equal(f, f1) and np.array_equal(g, g1)
    col = ev.sites.col[id(ev.plan)][0]                     # the root union's column
    assert set(np.unique(rec[:, col])) >= set(range(12))
    pinned = rec.copy()
    pinned[:, col] = 4                                      # every point on the fifth child
    f5, g5 = ev.pinned(P, pinned)
    want, gwant = ev_of(kids[4]).field_grad(P)
    np.testing.assert_allclose(f5, want, atol=1e-15)
    np.testing.assert_allclose(g5, gwant, atol=1e-12)


def test_a_stacked_groups_grid_records_and_pins_as_every_member_on_every_point(load_example, monkeypatch):
    # the train's car bodies are a stack whose groups (52 points, 5 subtracted boxes: a
    # union site) keep a grid: its candidates give the values, records and pins of
    # every member's primitives evaluated on every point
    from blobtree_ink.model import groups as G
    from blobtree_ink.model.stack import Stack
    ev = M.Evaluator(load_example("train"))
    cars = [c for c in ev.plan.children if isinstance(c, Stack) and c.shape.op == "blend"]
    assert len(cars) == 1 and cars[0].K == 5
    lo, hi = cars[0].lo, cars[0].hi
    P = lo + (hi - lo) * np.random.default_rng(11).random((4000, 3))
    f, g, table = ev.record(P)
    other = table[::-1].copy()                          # pins from other points: other sheets
    fp, gp = ev.pinned(P, other)
    monkeypatch.setattr(G, "SMALL_DENSE", 10 ** 12)      # every member on every point
    f2, g2, table2 = ev.record(P)
    assert np.array_equal(f, f2) and np.array_equal(g, g2) and np.array_equal(table, table2)
    fp2, gp2 = ev.pinned(P, other)
    assert np.array_equal(fp, fp2) and np.array_equal(gp, gp2)
    assert (fp != f).sum() > 100 and (f > ev.iso).any()
