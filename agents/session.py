"""A MASSRIS sampling session: a resumable stepper (paper sections 4-6).

    s = Session(model, View(eye=...), Settings(resolution=20, agents=10))
    s.request("OUTLINES")              # Table 1 requests, optionally in a Region
    while not s.done: s.step()         # or s.run(seconds=..., iterations=...)
    s.snapshot()                       # plain data: outlines, the rough mesh, progress

Initialisation polygonises the model, fills the blackboard and processes the polygon
edges into approximate feature points. Each system iteration the manager assigns the
highest-priority tasks to idle agents, every busy agent performs one action (a seed
refinement, a trace step, an exploration step), reports, and the blackboard and the
priorities of the touched neighbourhoods are updated. Once the polygon edges' seeds are
taken and at most DETAIL_AFTER traces are left, idle agents explore the voxels the
blackboard flags (corner normals that disagree) where no outline passes, for features
smaller than a cell (``Settings.explore_detail``). Iterations count from zero after
initialisation, as in the paper.

The session owns its parts and gives each only what it needs: the agent pool
(agents.pool), the tracing tasks (agents.traces), the explorers (agents.explore), the
blackboard and the surface queries. What it hands out is a :class:`Sampling` value
(its results: agents.results).
"""
import copy
import time

import numpy as np
from numpy.random import default_rng    # numpy imports it lazily: here, not in a run's first call

from ..blackboard.board import KIND_ID, VIEW_DEPENDENT, from_mesh
from ..blackboard.edges import process_edges
from ..blackboard.polygonise import polygonise
from ..model import Evaluator
from ..model.curvature import curvature, radial
from . import detail, manager, sheets
from .beside import seeds_beside_silhouettes
from .changes import EVERYWHERE
from .continuation import NO_WALKS, Continuation, Init, carried, seed_brackets, thin_walk_seeds
from .explore import Explorers
from .follow import follow
from .pool import AgentPool
from .results import Results
from .ridges import RidgeTraces
from .settings import Settings  # noqa: F401  (agents.session.Settings)
from .surface import Surface
from .traces import Traces

REQUESTS = ("OUTLINES", "FIND_FEATURES")      # the requests a sampling session serves (MASSRIS Table 1)
DETAIL_AFTER = 4            # traces left when the detail phase may start


class Session(Results):
    def __init__(self, model, view, settings=None, previous=None, remember=False):
        """``previous``: the last frame's session's Continuation, to go on from (see
        agents.continuation); ``remember``: keep this one's initialisation for the next."""
        self.settings = settings or Settings()
        self.settings.check()
        s = self.settings
        self.ev = model if isinstance(model, Evaluator) else Evaluator(model)
        self.view = view
        self.surface = Surface(self.ev, view)
        t0 = time.perf_counter()
        self.carried = carried(previous, self.ev.model, view.key(), s)
        self._walks = self.carried.walks          # the last frames' explorers' walks (the same model)
        init = self.carried.init
        if init is not None:                     # the same model: the last frame's polygonisation
            self.mesh, self.bb, curv = init.mesh, init.board_copy(), init.curvature
        else:
            self.mesh = polygonise(self.ev, int(s.resolution))
            self.bb, curv = from_mesh(self.mesh, self.ev, self._curvature)
            if remember:
                init = Init(self.mesh, copy.deepcopy(self.bb), curv, s.resolution)
        self._init = init if remember else None
        self.vertex_normals = curv["normal"]
        self.vertex_curvature = curv
        self.h = self.bb.h
        changed = self.carried.changed         # where the field changed since the last frame (None: nowhere)
        # seen from where the last frame's eye was, after a frame that ran to its end: every
        # kind is as its field is, the last frame's outside where it changed (but for the
        # detail phase of every REFRESH-th frame, which looks everywhere)
        self._static = self.carried.same_eye and self.carried.complete and changed is not EVERYWHERE
        kr = radial(curv, view.towards_eye(self.mesh.vertices))[0] if "suggestive" in s.kinds else None
        feats = process_edges(self.mesh, self.vertex_normals, curv["mean"], view, s.crease_angle, radial=kr)
        for kind in s.kinds:
            if kind == "ridges":                 # seeded from the vertices themselves (agents.ridges)
                continue
            pts, a, b = feats[kind]
            if kind not in VIEW_DEPENDENT and changed is not EVERYWHERE and self.carried.complete or self._static:
                # creases and curvature-sign lines do not depend on the eye (nor, seen from
                # where the last frame's eye was, do the others): where the field is the last
                # frame's, so are they (kept: all of them, its session having run to its
                # end), and its seeds would find them again
                here = np.zeros(len(pts), bool) if changed is None else changed.contains(pts, pad=self.h)
                pts, a, b = pts[here], a[here], b[here]
            self.bb.add_features(pts, a, b, kind)
        if s.explore_detail and changed is not None:           # the flagged voxels' corners where it changed
            detail.corner_features(self.bb, self.surface, s, None if changed is EVERYWHERE else
                                   self.bb.surface_rows[self._changed_here(self._voxel_centres(self.bb.surface_rows))])
        self.step_len = s.step * self.h
        self.tol = s.tolerance * self.ev.scale
        self._walls = np.zeros((0, 3))
        if s.explore_detail and changed is not None:
            self._walls, centres = detail.subtracted_walls(self.surface, self.h, self.ev.model.root)
            detail.subdivide(self.bb, self.surface, s, self._walls, centres)
        # the last frame's silhouettes followed where the eye moved; what was lost seeds the tracer
        moved = self.carried.seeds
        followed, lost = follow(self.surface, [o for o in moved if o.kind == "silhouette"], self.h, self.step_len,
                                self.tol, s.crease_angle)
        a, b, kinds = seed_brackets(lost + [o for o in moved if o.kind not in ("silhouette", "ridges")], self.h)
        for kind in sorted(set(kinds)):
            m = np.array(kinds) == kind
            self.bb.add_features(0.5 * (a[m] + b[m]), a[m], b[m], kind)
        self.priority = manager.priorities(self.bb, np.arange(self.bb.vox.n), s.lod)["priority"]
        self.init_seconds = time.perf_counter() - t0
        self.iteration = 0
        self.pool = AgentPool(s.agents)
        sites = self.ev.sites.count if sheets.usable(self.surface) else 0
        self.traces = Traces(self.surface, self.bb, self.pool, s, self.tol, self.step_len, sites)
        # the same model from a moved eye after a complete frame: only the lines that depend on the eye are new
        kinds = [k for k in s.kinds if k in VIEW_DEPENDENT] if self._walks is not None and self.carried.complete \
            and not self._static else s.kinds
        self.explorers = Explorers(self.surface, self.bb, self.pool, default_rng(s.seed), kinds, s.crease_angle,
                                   s.explore_steps)
        # the small silhouettes the last frames' walks cross, seen from here (those the outlines
        # kept or followed cross are taken as theirs)
        walk_seeds = None
        if self._walks is not None and "silhouette" in s.kinds and not self._static:
            walk_seeds = self._walks.seeds(self.view, self.bb, lost)
        # the last frame's outlines where nothing changed, and its silhouettes followed
        kept = self.carried.whole + self.carried.kept
        self.traces.add_traced(kept + followed)
        self.traces.extend(followed, len(kept))   # ... traced on from the followed ones' ends
        if self._walks is not None:
            self.explorers.explored.update(self._walks.rows)
        if walk_seeds is not None:
            thin_walk_seeds(self.bb, self.traces.traced, walk_seeds, 0.5 * self.step_len)
        # apparent ridges: their own agents, seeded from the vertices (where the field changed,
        # when the eye stayed and the last frame's session ran to its end: elsewhere its
        # ridges are kept) and from the last frame's when the eye moved
        V, gV = self.mesh.vertices, -curv["normal"] * curv["grad_norm"][:, None]
        here = np.full(len(V), "ridges" in s.kinds)
        if self._static:
            here &= False if changed is None else changed.contains(V, pad=self.h)
        V, gV = V[here], gV[here]
        self.ridges = RidgeTraces(self.surface, self.pool, self.traces.traced, self.step_len, s.max_outline_steps,
                                  V, gV, moved=[o for o in moved if o.kind == "ridges"])
        self.requests = []
        # flagged voxels queued for exploration, once (none where the field is the last frame's)
        nothing_new = self.carried.age and (self._static or self._walks is None)
        self._detail = np.zeros(0, np.int64) if changed is None and nothing_new else None
        self._missed = None         # probe points on the sheets the polygonisation missed, once looked for
        self._stitched = None       # (state, outlines) of the last stitching
        # looked where a silhouette may pass untraced (not to: seen as the last frame saw the same model)
        self._swept = not s.explore_detail or self._static
        self._swept_rows = np.zeros(0, np.int64)

    def _voxel_centres(self, rows):
        return self.bb.lo + (self.bb.vox["ijk"][rows] + 0.5) * self.h

    def _changed_here(self, P):
        """Which points lie where the field changed since the last frame (all without one,
        or when this frame's detail phase looks everywhere: agents.continuation)."""
        changed = self.carried.changed
        if changed is EVERYWHERE or self.carried.age == 0 or self._walks is not None and not self._static:
            return np.ones(len(P), bool)
        if changed is None:
            return np.zeros(len(P), bool)
        return changed.contains(P, pad=self.h)

    def continuation(self):
        """What this session leaves the next frame's (agents.continuation)."""
        walks, swept = None, frozenset()
        if self._init is not None:            # the explored rows of the model's own board (the same in every frame)
            rows = [r for r in self.explorers.explored if r < self._init.board.vox.n]
            walks = (self._walks or NO_WALKS).joined(self.explorers.walks(), rows)
            mine = self._swept_rows if self.done else ()          # (looked in, and what was found there traced)
            swept = self.carried.swept | {int(r) for r in mine if r < self._init.board.vox.n}
        return Continuation(self.ev.model, self.view.key(), self.settings, tuple(self.outlines()), self._init,
                            self.carried.age, self.done, walks, swept)

    def _curvature(self, P, g):
        return curvature(self.ev, P, g)

    def _explorer_starts(self):
        """Where explorers start: on the sheets the rough polygonisation missed (parts
        thinner than a cell: detail.missed_sheets), whose voxels join the blackboard
        as surface voxels the first time this is asked (their corners flagged for
        features like the polygon's, their neighbourhood's priorities updated), and on
        the walls of subtracted parts (found at initialisation, where they subdivide
        voxels)."""
        if self._missed is None:
            self._missed = np.zeros((0, 3))
            if self.settings.explore_detail:
                mesh, self._missed = detail.missed_sheets(self.ev, self.mesh)
                k = len(self.mesh.vertices)
                if len(mesh.vertices) > k:
                    rows, curv = self.bb.add_surface(mesh.cells[k:], mesh.vertices[k:], self.ev, self._curvature)
                    self.mesh = mesh
                    self.vertex_normals = np.concatenate([self.vertex_normals, curv["normal"]])
                    self.vertex_curvature = {key: np.concatenate([v, curv[key]])
                                             for key, v in self.vertex_curvature.items()}
                    detail.corner_features(self.bb, self.surface, self.settings, rows)
                    self._reprioritise(rows)
        return np.concatenate([self._missed, self._walls])

    def _priorities(self):
        """Equation 3's priority of every voxel; a voxel the blackboard made since the last
        update (a feature point or sample in a new voxel) has 0 until it is updated."""
        n = self.bb.vox.n
        if len(self.priority) < n:
            self.priority = np.concatenate([self.priority, np.zeros(n - len(self.priority))])
        return self.priority

    def _reprioritise(self, rows):
        """Equation 3's priorities again for the voxels around these (new ones start at 0)."""
        mark = np.zeros(self.bb.vox.n, bool)
        mark[rows] = True
        nb = self.bb.neighbours(np.flatnonzero(mark))
        mark[:] = False
        mark[nb[nb >= 0]] = True
        around = np.flatnonzero(mark)
        self._priorities()[around] = manager.priorities(self.bb, around, self.settings.lod)["priority"]

    def _queue_detail(self):
        """Once the polygon edges' seeds are taken and few traces are left: send explorers
        to the sheets the polygonisation missed and the walls of subtracted parts
        (:meth:`_explorer_starts`), seed the silhouettes beside the traced fragments
        (agents/beside.py), and explore the flagged voxels (corner normals that disagree)
        no traced outline passes through, by priority, for outlines smaller than a cell."""
        outlines = [r for k, r in self.requests if k == "OUTLINES"]
        # the missed sheets and subtracted walls: explored in the frames the walks come from
        starts = self._explorer_starts() if outlines and self._walks is None else np.zeros((0, 3))
        starts = starts[self._changed_here(starts)]
        self._detail = detail.flagged_voxels(self.bb, self.surface, self.settings)
        self._detail = self._detail[self._changed_here(self._voxel_centres(self._detail))]
        if not outlines:
            return
        # explorers start on the missed sheets and the subtracted walls first (an
        # outline request's: the polygon's seeds, traced by then, find most outlines)
        for region in outlines:
            self.explorers.enqueue_starts(starts, region)
        if "silhouette" in self.settings.kinds:
            seeds_beside_silhouettes(self.traces.done + self.traces.active_outlines(), self.surface, self.bb,
                                     self.traces.traced, self.step_len, self.settings.crease_angle,
                                     lambda P: self._in_regions(P) & self._changed_here(P))
        if len(self._detail) == 0:
            return
        rows = self._detail[self._in_regions(self._voxel_centres(self._detail))]
        pts = self.traces.traced.points()
        if len(pts):
            covered = self.bb.voxel_rows(self.bb.voxel_of(pts), create=False)
            rows = rows[~np.isin(rows, covered)]
        self.explorers.enqueue(rows[np.argsort(-self._priorities()[rows], kind="stable")])

    # --- requests (Table 1) -----------------------------------------------------------
    def request(self, kind, region=None):
        if kind not in REQUESTS:
            raise ValueError(f"unknown request {kind!r}; one of {', '.join(REQUESTS)}")
        self.requests.append((kind, region))
        if kind == "FIND_FEATURES":
            self._queue_exploration(region, all_surface=True)
        elif kind == "OUTLINES" and region is not None:
            self._queue_exploration(region, all_surface=False)
        if kind == "FIND_FEATURES":
            self.explorers.enqueue_starts(self._explorer_starts(), region)

    def _queue_exploration(self, region, all_surface):
        v = self.bb.vox
        rows = np.flatnonzero(v["surface"][:v.n])
        if region is not None:
            centres = self.bb.lo + (v["ijk"][rows] + 0.5) * self.h
            rows = rows[region.contains(centres)]
        if not all_surface:
            rows = rows[self._priorities()[rows] > np.median(self.priority[rows])] if len(rows) else rows
        self.explorers.enqueue(rows[np.argsort(-self._priorities()[rows], kind="stable")])

    def _in_regions(self, P, kind="OUTLINES"):
        regions = [r for k, r in self.requests if k == kind]
        if not regions:
            return np.zeros(len(P), bool)
        if any(r is None for r in regions):
            return np.ones(len(P), bool)
        return np.any([r.contains(P) for r in regions], axis=0)

    # --- the system iteration ---------------------------------------------------------
    @property
    def tasks_left(self):
        return len(self._open_seeds()) + len(self.explorers.queue) + len(self.traces) + len(self.explorers) + \
            self.ridges.waiting(self._in_regions) + len(self.ridges)

    @property
    def _idle(self):
        """No task left, nor the detail phase (explorers, seeds beside silhouettes) to come."""
        return self.tasks_left == 0 and not (self.settings.explore_detail and self._detail is None and self.requests)

    @property
    def done(self):
        """Idle, the voxels where traces were lost subdivided (agents.detail.subdivide_at)
        and those where a silhouette may pass untraced (agents.detail.unfound_silhouettes)."""
        return self._idle and not self.traces.lost and (self._swept or not self.requests)

    def _open_seeds(self):
        ids = self.bb.open_features()
        if len(ids) == 0:
            return ids
        kinds = self.bb.feat["kind"][ids]
        ok = np.isin(kinds, [KIND_ID[k] for k in self.settings.kinds])
        ids = ids[ok]
        return ids[self._in_regions(self.bb.feat["pos"][ids])]

    def step(self):
        """One system iteration; returns False when there was nothing left to do."""
        if self.done:
            return False
        if self._walks is not None and self._detail is None and self.settings.explore_detail and self.requests:
            self._queue_detail()      # going on with the same model: a small detail phase, started at once
        if self._idle and self.traces.lost:      # nothing else to do: subdivide where traces were lost
            detail.subdivide_at(self.bb, self.surface, self.settings, self.traces.take_lost(),
                                going_on=self.carried.init is not None)
        elif self._idle and not self._swept and self.requests:    # ... then, once, where a silhouette may pass
            self._swept = True                                      # untraced
            self._swept_rows = detail.unfound_silhouettes(self.bb, self.surface, self.settings, self.outlines(),
                                                          self._in_regions, self.carried.swept)
        self._assign()
        touched = self.traces.step() + self.explorers.step()
        self.ridges.step()
        if touched:
            self._reprioritise(np.concatenate(touched))
        self.iteration += 1
        # the detail phase starts once the edge seeds are taken and only a few traces are
        # left (a long outline's last steps take many cheap iterations)
        quiet = len(self.traces) <= DETAIL_AFTER and not (len(self.explorers) or self.explorers.queue)
        if self.settings.explore_detail and self._detail is None and quiet and len(self._open_seeds()) == 0:
            self._queue_detail()
        return True

    def run(self, seconds=None, iterations=None):
        t0 = time.perf_counter()
        n = 0
        while not self.done:
            if iterations is not None and n >= iterations:
                break
            if seconds is not None and time.perf_counter() - t0 >= seconds:
                break
            self.step()
            n += 1
        return n

    def _assign(self):
        seeds = self._open_seeds()
        if len(seeds) and len(self.pool):
            pr = self._priorities()[self.bb.feat["voxel"][seeds]]
            seeds = seeds[np.argsort(-pr, kind="stable")]
            take = []
            budget = len(self.pool)
            for s in seeds:
                need = 2 if self.bb.feat["kind"][s] == KIND_ID["crease"] else 1
                if need > budget:
                    break
                budget -= need
                take.append(s)
            if take:
                self.traces.start(np.array(take), self.iteration)
        self.ridges.assign(self._in_regions)
        self.explorers.assign()
