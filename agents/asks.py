"""Solvers that share evaluator batches.

A solver written as a generator yields the points it needs the field at (an
:class:`Ask`) and is sent back f and grad f there. :func:`run` steps several solvers
in lockstep, each round one evaluation of every live solver's points. An evaluation
costs about as much on 100 points as on 2000 (the plan's tree walk: on the train
0.85 ms against 1.6 ms), so independent solvers cost the longer of their chains of
evaluations, not their sum. A solver run alone is a lockstep of one: there is one code
path.

An ask with branch records (``pins``, model.branches) is evaluated with those choices
pinned, and one with ``record`` is sent back its points' records too; a round holding
either evaluates every other ask's points with NOT_REACHED rows, which is the plain
field there (Evaluator.pinned, or Evaluator.choose for records and pins together).
"""
from typing import NamedTuple

import numpy as np

from ..model.branches import NOT_REACHED


class Ask(NamedTuple):
    P: np.ndarray               # (n, 3) points
    pins: object = None         # (n, sites) int32 branch records to pin, or None
    record: bool = False        # send back (f, g, records) rather than (f, g)


def run(ev, *solvers):
    """Run the generators ``solvers`` (None: nothing to run) in lockstep on ``ev``;
    returns their return values (None for a None), in order."""
    out = [None] * len(solvers)
    asks = {}
    for i, s in enumerate(solvers):
        if s is not None:
            _advance(s, i, None, asks, out)
    while asks:
        order = sorted(asks)
        items = [asks[i] for i in order]
        f, g, table = _evaluate(ev, items)
        at = np.cumsum([0] + [len(a.P) for a in items])
        asks = {}
        for k, i in enumerate(order):
            part = slice(at[k], at[k + 1])
            reply = (f[part], g[part], table[part]) if items[k].record else (f[part], g[part])
            _advance(solvers[i], i, reply, asks, out)
    return out


def _evaluate(ev, items):
    """One evaluation of the asks ``items``, their points in order: f, g and the
    choices (None where no ask has pins or wants records)."""
    P = items[0].P if len(items) == 1 else np.concatenate([a.P for a in items])
    record = any(a.record for a in items)
    if not record and not any(a.pins is not None for a in items):
        return (*ev.field_grad(P), None)
    if len(items) == 1 and not record:
        return (*ev.pinned(P, items[0].pins), None)           # read only: no copy
    table = np.concatenate([a.pins.astype(np.int32) if a.pins is not None else
                            np.full((len(a.P), ev.sites.count), NOT_REACHED, np.int32) for a in items])
    if record:
        return (*ev.choose(P, table), table)
    return (*ev.pinned(P, table), None)


def _advance(solver, i, reply, asks, out):
    try:
        ask = solver.send(reply)
    except StopIteration as stop:
        out[i] = stop.value
        return
    if not isinstance(ask, Ask):
        raise TypeError(f"a solver must yield Ask, got {type(ask).__name__}")
    asks[i] = ask
