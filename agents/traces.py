"""Tracing tasks of a session: a seed's refinement starts them (one task each way
along its outline where agents are free for both), every system iteration steps them
together (tracer.trace_step), and a finished one hands its points to the session as
an outline. Functions of the session (``self``), which holds the tasks."""
from dataclasses import dataclass, field

import numpy as np

from ..blackboard.board import FEATURE_KINDS, KIND_ID
from . import crease_seeds
from .outline import Outline
from .tracer import refine_seeds, trace_step
from .traced import NO_ARC, SELF_GAP, consume_crossed

SEED_PAUSE = 8          # bisection iterations a seed's refinement takes per system iteration
SEED_ROUNDS = 6         # ... in at most this many system iterations


@dataclass
class Trace:
    kind: int
    agents: tuple
    p: np.ndarray
    t: np.ndarray
    ref: np.ndarray
    start: np.ndarray
    start_t: np.ndarray
    start_ref: np.ndarray
    fwd: list = field(default_factory=list)
    fwd_n: list = field(default_factory=list)
    bwd: list = field(default_factory=list)
    bwd_n: list = field(default_factory=list)
    phase: str = "fwd"
    closed: bool = False
    h: float = 0.0              # current step: halved after a failed step, regrown after success
    base: float = 0.0           # its full step: the session's, or a subdivided voxel's seed's
    id: int = -1
    sides: tuple = None         # a crease's last point, side directions and side facings
    start_sides: tuple = None   # the same at its seed
    paired: bool = False        # the other half (backwards from the seed) is its own task
    start_n: np.ndarray = None  # the normal at its seed
    pins: np.ndarray = None     # a crease team's branch records, side A and side B (agents.sheets)
    team: tuple = None          # the team's side positions (A, B) at its last point
    start_pins: np.ndarray = None
    start_team: tuple = None


def start(self, ids):
    """Refine the seeds ``ids`` (taken from the blackboard) and start a task on each
    valid one that no traced outline passes."""
    f = self.bb.feat
    self.bb.consume(ids)
    kinds = f["kind"][ids].astype(np.int64)
    X, n, T, ref, A, B, valid, pins, opened = refine_seeds(self.surface, kinds, f["a"][ids], f["b"][ids],
                                                           self.tol, self.settings.crease_angle, pause=SEED_PAUSE)
    requeue(self, ids[opened], A[opened], B[opened])
    sides = {}
    cre = np.flatnonzero(valid & (kinds == KIND_ID["crease"]))
    if len(cre) and "silhouette" in self.settings.kinds:
        sides = dict(zip(cre, crease_seeds.seed_sides(self, X[cre], A[cre], B[cre])))
    base = self.settings.step * f["cell"][ids]          # the seed's scale sets its trace's step
    needs = np.where(kinds == KIND_ID["crease"], 2, 1)
    later = int(needs[valid].sum())          # agents the seeds still to start need, one way
    todo = np.flatnonzero(valid)
    # is an outline traced through the seed already (or through a seed started before it)?
    m = len(todo)
    loop = self.traced.loop(kinds[todo], X[todo], base[todo], n=n[todo], upto=np.arange(m),
                            new=(kinds[todo], X[todo], n[todo], np.zeros(m), np.zeros(m), base[todo]))
    for j, i in enumerate(todo):
        k, need = int(kinds[i]), int(needs[i])
        later -= need
        if loop.hit(j) is not None:
            continue
        # a task each way from the seed where agents are free for both, after every
        # seed taken has its first (a seed left open may be consumed by a trace that
        # crosses its bracket on a neighbouring outline): an outline between two
        # seeds is then traced from both ends at once, in half the iterations;
        # otherwise one task goes forwards, then backwards
        paired = len(self.free) - later >= 2 * need
        tid = len(self.done_outlines) + len(self.traces) + 1000000 * self.iteration
        for phase in ("fwd", "bwd") if paired else ("fwd",):
            agents = tuple(self.free.pop() for _ in range(need))
            tr = Trace(kind=k, agents=agents, p=X[i], t=T[i] if phase == "fwd" else -T[i], ref=ref[i],
                       start=X[i], start_t=T[i], start_ref=ref[i], id=tid, h=float(base[i]),
                       base=float(base[i]), phase=phase, paired=paired, start_n=n[i])
            tr.sides = tr.start_sides = sides.get(i)
            tr.pins = tr.start_pins = pins[i]
            tr.team = tr.start_team = (A[i], B[i])
            self.traces.append(tr)
        self.traces[-1 - paired].fwd.append(X[i])
        self.traces[-1 - paired].fwd_n.append(n[i])
        loop.keep(j, tid)
    loop.commit()


def requeue(self, ids, A, B):
    """Seeds whose bisection paused (one agent action per system iteration) go back on
    the blackboard with their narrowed brackets, to be refined again in a later
    iteration; one that has paused SEED_ROUNDS times already is dropped (a bracket
    still narrowing after that many bisections holds no outline point it can reach)."""
    f = self.bb.feat
    rounds = f["rounds"][ids] + 1
    keep = rounds < SEED_ROUNDS
    for k in np.unique(f["kind"][ids[keep]]):
        m = keep & (f["kind"][ids] == k)
        self.bb.add_features(0.5 * (A[m] + B[m]), A[m], B[m], FEATURE_KINDS[k], f["cell"][ids[m]], rounds[m])


def step(self):
    """One trace step of every task; returns the blackboard rows the new points touched."""
    if not self.traces:
        return []
    trs = self.traces
    kinds = np.array([t.kind for t in trs])
    P = np.array([t.p for t in trs])
    T = np.array([t.t for t in trs])
    ref = np.array([t.ref for t in trs])
    h = np.array([t.h for t in trs])
    base = np.array([t.base for t in trs])
    nP = np.array([t.fwd_n[-1] if t.phase == "fwd" else t.bwd_n[-1] if t.bwd_n else t.start_n for t in trs])
    retry = h > base / 16                  # a failed step may still be halved
    pins = np.array([t.pins for t in trs])
    team = tuple(np.array([t.team[k] for t in trs]) for k in (0, 1))
    st = trace_step(self.surface, kinds, P, T, ref, h, self.tol, self.settings.crease_angle, nP, retry, pins, team)
    X, n, Tn, refn, ok = st.X, st.n, st.T, st.ref, st.ok
    side_seeds = crease_seeds.silhouettes_off_creases(self, trs, X, st.A, st.B, st.nA, st.nB, ok)
    rows = self.bb.add_samples(X, st.f, st.g, "path")
    # how far each new point is from its outline's other end: the seed, or the forward
    # half's last point for a backward half
    other = np.array([t.start if t.phase == "fwd" or not t.fwd else t.fwd[-1] for t in trs])
    at_other = np.linalg.norm(X - other, axis=1) < 0.75 * base
    arcs = np.array([len(t.fwd) if t.phase == "fwd" else -(len(t.bwd) + 1) for t in trs], np.int64)
    ids = np.array([t.id for t in trs], np.int64)
    # which outline each new point meets (and, for a forward half ending without its
    # pair, whether one passes its seed), in loop order: see traced.Loops
    got = np.flatnonzero(ok)
    q = np.full(len(trs), -1)
    q[got] = np.arange(len(got))
    lone = np.flatnonzero([t.phase == "fwd" and not t.paired for t in trs])
    sw = np.full(len(trs), -1)
    sw[lone] = len(got) + np.arange(len(lone))
    loop = self.traced.loop(
        np.concatenate([kinds[got], kinds[lone]]),
        np.concatenate([X[got], np.array([trs[i].start for i in lone]).reshape(-1, 3)]),
        np.concatenate([base[got], base[lone]]), np.concatenate([ids[got], ids[lone]]),
        np.concatenate([arcs[got], np.full(len(lone), NO_ARC)]),
        np.concatenate([n[got], np.array([trs[i].fwd_n[0] for i in lone]).reshape(-1, 3)]),
        new=(kinds[got], X[got], n[got], ids[got], arcs[got], base[got]),
        upto=np.concatenate([np.arange(len(got)), np.searchsorted(got, lone)]))
    q, sw = q.tolist(), sw.tolist()
    still = []
    covered = []                           # trace points appended this iteration
    for i, tr in enumerate(trs):
        end = None
        if not ok[i] and retry[i]:
            tr.h *= 0.5                    # retry with a shorter step next iteration
            still.append(tr)
            continue
        if not ok[i]:
            end = "lost"
        else:
            mine = tr.fwd if tr.phase == "fwd" else tr.bwd
            steps = len(tr.fwd) + len(tr.bwd)
            if steps >= 4 and at_other[i]:
                end = "closed"
            elif (hit := loop.hit(q[i])) is not None:
                # an outline is here: stop short; come round onto its own seed, it closed
                end = "closed" if tr.phase == "fwd" and hit[0] == tr.id and hit[1] <= SELF_GAP else "joined"
            elif steps >= self.settings.max_outline_steps:
                end = "limit"
            else:
                mine.append(X[i])
                (tr.fwd_n if tr.phase == "fwd" else tr.bwd_n).append(n[i])
                loop.keep(q[i])
                tr.p, tr.t, tr.ref = X[i], Tn[i], refn[i]
                tr.pins, tr.team = st.pins[i], (st.A[i], st.B[i])
                tr.h = min(tr.base, 1.5 * tr.h)
                covered.append(i)
        if end is None:
            still.append(tr)
        elif end == "closed":
            tr.closed = True
            finish(self, tr)
        elif tr.phase == "fwd" and not tr.paired and loop.hit(sw[i]) is None:
            tr.phase = "bwd"           # trace the other way from the seed
            tr.p, tr.t, tr.ref = tr.start, -tr.start_t, tr.start_ref
            tr.h = tr.base
            tr.sides = tr.start_sides
            tr.pins, tr.team = tr.start_pins, tr.start_team
            still.append(tr)
        else:
            finish(self, tr)
    loop.commit()
    self.traces = still
    W = np.where((kinds == KIND_ID["crease"])[:, None], refn, np.cross(n, Tn))
    W /= np.maximum(np.linalg.norm(W, axis=1, keepdims=True), 1e-300)
    consume_crossed(self, kinds[covered], X[covered], n[covered], W[covered], base[covered])
    if side_seeds:
        a, b, cell = (np.array([x[i] for x in side_seeds]) for i in range(3))
        self.bb.add_features(0.5 * (a + b), a, b, "silhouette", cell)
    return [rows]


def finish(self, tr):
    """A task is done: its agents are free again and its points become an outline."""
    pts = tr.bwd[::-1] + tr.fwd
    nrm = tr.bwd_n[::-1] + tr.fwd_n
    self.free.extend(tr.agents)
    if pts:                    # even a single point: other traces stopped short of it
        self.done_outlines.append(Outline(FEATURE_KINDS[tr.kind], np.array(pts), np.array(nrm), tr.closed,
                                          tr.base))
