"""Solvers on shared evaluations (agents.asks) and the evaluation that takes records
and pins together (Evaluator.choose): each round is one evaluation, and every solver
gets exactly what it would have got alone."""
import numpy as np
import pytest

from blobtree_ink import model as M
from blobtree_ink.agents.asks import Ask, run
from blobtree_ink.model.branches import NOT_REACHED

from conftest import ALL_MODELS


class Counting:
    """An evaluator that counts its calls (and the points of each)."""
    def __init__(self, ev):
        self.ev, self.calls = ev, []
        self.sites = ev.sites

    def _n(self, P):
        self.calls.append(len(P))

    def field_grad(self, P):
        self._n(P)
        return self.ev.field_grad(P)

    def pinned(self, P, table):
        self._n(P)
        return self.ev.pinned(P, table)

    def choose(self, P, table):
        self._n(P)
        return self.ev.choose(P, table)


def points(ev, n, seed):
    lo, hi = ev.bounds
    return lo + (hi - lo) * np.random.default_rng(seed).random((n, 3))


def plain(P, rounds, log):
    for k in range(rounds):
        f, g = yield Ask(P + 0.01 * k)
        log.append(("plain", k, f, g))
    return "plain done"


def pinned(P, pins, log):
    f, g = yield Ask(P, pins)
    log.append(("pinned", 0, f, g))
    return "pinned done"


def recording(P, log):
    f, g, rec = yield Ask(P, record=True)
    log.append(("record", 0, f, g, rec))
    return "record done"


@pytest.mark.parametrize("name", ["train", "csg_difference"])
def test_solvers_side_by_side_share_each_round_and_get_what_they_would_alone(name, load_example):
    ev = M.Evaluator(load_example(name))
    P, Q, R = points(ev, 300, 1), points(ev, 200, 2), points(ev, 100, 3)
    _, _, pins = ev.record(points(ev, 200, 4))            # other points' choices, pinned at Q
    alone = []
    for s in (plain(P, 3, alone), pinned(Q, pins, alone), recording(R, alone)):
        assert run(ev, s)[0].endswith("done")
    log = []
    counting = Counting(ev)
    out = run(counting, plain(P, 3, log), None, pinned(Q, pins, log), recording(R, log))
    assert out == ["plain done", None, "pinned done", "record done"]
    # three rounds: all three asks, then the plain solver's two more alone
    assert counting.calls == [600, 300, 300]
    assert [e[:2] for e in log] == [("plain", 0), ("pinned", 0), ("record", 0), ("plain", 1), ("plain", 2)]
    by = {e[:2]: e[2:] for e in alone}
    for e in log:
        for x, y in zip(e[2:], by[e[:2]]):
            assert np.array_equal(x, y)
    # what each got is the evaluator's own answer
    f, g = ev.pinned(Q, pins)
    assert np.array_equal(by[("pinned", 0)][0], f) and np.array_equal(by[("pinned", 0)][1], g)
    f, g, rec = ev.record(R)
    assert np.array_equal(by[("record", 0)][2], rec) and np.array_equal(by[("record", 0)][0], f)


@pytest.mark.parametrize("name", ALL_MODELS)
def test_choose_pins_the_pinned_rows_and_records_the_others(name, load_example):
    ev = M.Evaluator(load_example(name))
    P = points(ev, 2000, 5)
    _, _, other = ev.record(points(ev, 2000, 6))
    f0, g0, rec = ev.record(P)
    fp, gp = ev.pinned(P, other)
    table = np.where(np.arange(len(P))[:, None] % 2 == 0, other, NOT_REACHED).astype(np.int32)
    f, g = ev.choose(P, table)
    even, odd = np.arange(0, len(P), 2), np.arange(1, len(P), 2)
    assert np.array_equal(f[even], fp[even]) and np.array_equal(g[even], gp[even])
    assert np.array_equal(f[odd], f0[odd]) and np.array_equal(g[odd], g0[odd])
    assert np.array_equal(table[odd], rec[odd])
    # a pinned row keeps its pins where it had them
    had = other[even] != NOT_REACHED
    assert np.array_equal(table[even][had], other[even][had])
    with pytest.raises(ValueError, match="int32"):
        ev.choose(P, table.astype(np.int64))


def test_a_solver_must_ask_for_points_and_its_errors_reach_the_caller(load_example):
    ev = M.Evaluator(load_example("train"))

    def wrong():
        yield np.zeros((2, 3))

    def failing():
        yield Ask(np.zeros((1, 3)))
        raise RuntimeError("solver failed")

    with pytest.raises(TypeError, match="Ask"):
        run(ev, wrong())
    with pytest.raises(RuntimeError, match="solver failed"):
        run(ev, plain(np.zeros((2, 3)), 3, []), failing())
