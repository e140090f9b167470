"""The illustration pipeline: a resumable stepper from a :class:`~.job.Job` to plain
strokes by layer. The modal operator (on its worker thread), the background operator
and the command line drive this one stepper: one job, the same strokes on each path.

    ill = Illustration(job)            # cheap: nothing is computed yet
    while ill.step(): ...              # each step is one unit of work
    ill.result()                       # a Result at any time: what is made so far

The stages, in order: initialisation (polygonisation, the blackboard, sub-cell
features: the slow part of a big model), the agents' system iterations (while outlines
are wanted), the visible outlines (hidden lines removed against the exact surface), then
the style's stroke layers one by one (hatching, cross-hatching, strokes from the feature
chains, short strokes, stipples), each in parts of its starts (the model's own marks,
model.marks, whose choices are theirs: a layer does not depend on the layers drawn
before it, but for stipples drawn finer beside the outlines, nor a frame on the
frames before it), and a single stroke. :meth:`Illustration.stop` skips what is left
but the outlines of what was traced: a stopped illustration keeps every layer it
finished, and the outlines found so far with their hidden lines removed.
"""
import time
from dataclasses import replace

import numpy as np

from ..agents import Session
from ..blackboard.view import View
from ..model import Evaluator, key_of
from ..model.owners import owners
from ..strokes.data import LAYER_OF_KIND, StrokeSet
from ..strokes.paper import Placed
from . import hiding as HD
from . import layers as LY
from .continuation import Continuation
from .framing import bounds, default_light, inside, line_radius, point_text, stroke_unit, view_eye
from .job import FIND_FEATURES, JobError, OUTLINES, PLACE_STROKES, SINGLE_LAYER, SINGLE_STROKE, STYLE_LAYERS, Around
from .result import Progress, Result

# each stage's share of a run, for the progress figure (sampling: the share of the
# seeds taken; the stroke layers share theirs equally)
SHARES = {"init": 0.15, "sampling": 0.5, "outlines": 0.1, "strokes": 0.25}
STROKE_STAGES = ("hatching", "cross-hatching", "chains", "short", "stipples")


class Illustration:
    def __init__(self, job, previous=None, remember=False):
        """``previous``: the last frame's Continuation (pipeline.continuation), to go on
        from; ``remember``: keep what the next frame's can take (:meth:`continuation`)."""
        self.job = job.checked()
        self.previous, self.remember = previous, remember
        # the compiled model and its key, the eye, the light and the model's centre: made by the initialisation
        self.ev = self.model_key = self.eye = self.light = self.centre = None   # (on a runner's worker)
        self.requests = self.job.requests
        self.style = self.job.style
        self.session = None
        self.sampling = None           # the session's snapshot once its sampling ended
        self._live = None              # ... and while it runs (the fragments traced so far)
        self.line_radius = None
        self.canvas = None             # what the layers are drawn with (pipeline.layers.Canvas)
        self.hiders = None             # the other models that hide its lines (pipeline.hiding.hiders)
        self.layers = {}               # layer name -> strokes finished
        self.outline_set = None        # the visible outlines (a StrokeSet), once that stage ran
        self._lines_kept = None        # ... as the ink keeps them (_drawn_lines)
        self.warnings = []
        if PLACE_STROKES in self.job.kinds and not self.job.stroke_switches():
            self.warnings.append("the style draws no strokes: turn on Hatching, Stipples, Chain Strokes or "
                                 "Short Strokes, or pick a preset")
        st = self.style
        if "hatching" in self.job.stroke_switches() and st.cross_hatching and st.cross_field == st.hatch_field \
                and st.hatch_field != "straight":                 # (straight: each stroke its own way)
            self.warnings.append("the cross-hatching runs along the hatching (its Cross Field is the Flow Field): "
                                 "pick another Cross Field")
        self.owned = self.job.owned_layers()
        self.stages = self._plan()
        self.at = 0                    # the stage being worked on
        self.completed = []            # the stages done (a stop skips the rest)
        self._parts, self._part = None, 0  # a stroke layer's parts, and the next one to draw
        self._dots = None                  # ... and the stipples drawn so far (strokes.paper.Placed)
        self._lines = None                 # ... and the hatching's lines so far (strokes.paper.Placed)
        self.stopping = False
        self.finished = False
        self._fraction = 0.0
        self._seconds = 0.0
        self._sampling_seconds = 0.0   # the agents' iterations alone (the job's time budget)

    def _plan(self):
        j = self.job
        stages = ["init"]
        if j.wants_outlines():
            stages.append("sampling")
        if j.wants_outline_layers():
            stages.append("outlines")
        for switch in j.stroke_switches():
            stages.append(switch)
            if switch == "hatching" and self.style.cross_hatching:
                stages.append("cross-hatching")
        if SINGLE_STROKE in j.kinds:
            stages.append("single")
        return stages

    # --- stepping ---------------------------------------------------------------------
    @property
    def stage(self):
        return self.stages[self.at] if self.at < len(self.stages) else "done"

    def position(self):
        """Where the illustration is: the stage being worked on and the parts of it done
        (a stroke layer's; 0 for the other stages)."""
        return self.stage, (self._part if self._parts is not None else 0)

    def stop(self):
        """Finish early: what is left is skipped, except the visible outlines of what
        was traced (the next :meth:`step` draws them)."""
        self.stopping = True

    def step(self):
        """One unit of work; returns False once the illustration is finished."""
        if self.finished:
            return False
        t = time.perf_counter()
        stage = self.stage
        if self.stopping and stage not in ("init", "outlines"):
            if stage == "sampling" and "outlines" in self.stages:
                self.sampling = self.session.snapshot()
                self.at = self.stages.index("outlines")
            else:
                if self._parts:                # a layer stopped part-way: what it drew stays its own
                    self.completed.append(stage)
                self.at = len(self.stages)
            self._parts = None
            stage = self.stage
        if self.stopping and stage == "init":
            self.at = len(self.stages)
            stage = "done"
        if stage == "done":
            self.finished = True
            return False
        getattr(self, "_" + stage.replace("-", "_"))()
        took = time.perf_counter() - t
        self._seconds += took
        if stage == "sampling":
            self._sampling_seconds += took
        if self.at >= len(self.stages):
            self.finished = True
        return not self.finished

    def run(self):
        """Every step to the end; returns the result."""
        while self.step():
            pass
        return self.result()

    def _next(self):
        self.completed.append(self.stage)
        self.at += 1

    def _init(self):
        j = self.job
        prev = self.previous
        if isinstance(j.model, Evaluator):
            self.ev = j.model
        elif prev is not None and prev.ev.model == j.model:
            self.ev = prev.ev                  # the last frame's model: its plan, size and marks as made
        else:
            self.ev = Evaluator(j.model)
        self.model_key = key_of(self.ev)
        centre, radius = bounds(self.ev)
        self.centre = centre
        self.eye = view_eye(j.view, centre, radius)
        if inside(self.ev, self.eye):       # (an empty drawing: a frame of a camera passing through is one)
            self.warnings.append(f"the eye at {point_text(self.eye)} is inside the model: it sees nothing of it; "
                                 "move the camera (or the view) out of it")
        if j.light is not None:
            light = np.asarray(j.light, float)
        elif j.light_at is not None and np.linalg.norm(np.asarray(j.light_at, float) - centre) > 0:
            at = np.asarray(j.light_at, float)
            if inside(self.ev, at):
                raise JobError(f"the light at {point_text(at)} is inside the model: every point of its surface "
                               "would be in its own shadow; move the light out of it")
            light = at - centre
        else:
            light = default_light(centre, self.eye)
        self.light = light / np.linalg.norm(light)
        self.requests = tuple(replace(r, region=r.region.region(radius)) if isinstance(r.region, Around) else r
                              for r in j.requests)
        self.line_radius = line_radius(self.ev)
        self.canvas = LY.Canvas(self.ev, self.eye, self.light, self.line_radius, stroke_unit(self.ev),
                                settled=prev is not None and prev.ev is self.ev,
                                sight=LY.sight(self.ev, j.occluders, prev.occluders if prev is not None else ()))
        self.hiders = HD.hiders(self.ev, self.eye, self.canvas.sight)      # what the result records of them
        self.session = Session(self.ev, View(eye=self.eye), j.settings,
                               previous=prev.session if prev is not None else None, remember=self.remember)
        vertices = self.session.snapshot(stitch=False).vertices
        if len(vertices) == 0:
            self.warnings.append(f"the grid ({j.settings.resolution}) found no surface: the model's parts are thinner "
                                 f"than a cell ({self.session.h:.3g} wide), so outlines are missed; raise the grid")
        self._check_regions(vertices)
        if j.wants_outlines():
            for r in self.requests:
                if r.kind == FIND_FEATURES:
                    self.session.request(FIND_FEATURES, r.region)
            self.session.request(OUTLINES)
        if "sampling" not in self.stages:
            self.sampling = self.session.snapshot()
        self._next()

    def _check_regions(self, vertices):
        """A region request whose region holds no part of the surface (none of the rough
        mesh's vertices) says so; Place Strokes then draws nothing and replaces nothing."""
        for r in self.requests:
            if r.region is None or r.region.contains(vertices).any():
                continue
            what = "Place Strokes draws nothing" if r.kind == PLACE_STROKES else "no more detail is looked for"
            self.warnings.append(f"the region holds no part of the model's surface: {what}")
            if r.kind == PLACE_STROKES:
                strokes = set(STROKE_STAGES)
                self.stages = self.stages[:self.at + 1] + [s for s in self.stages[self.at + 1:] if s not in strokes]
                self.owned = tuple(x for x in self.owned if x not in STYLE_LAYERS.values())

    def _sampling(self):
        s = self.session
        out_of_time = self.job.seconds is not None and self._sampling_seconds >= self.job.seconds
        if out_of_time or not s.step() or s.done:
            self.sampling = s.snapshot()
            self._next()
        self._live = None

    def _current(self):
        """The sampling as it is now (while the agents trace: their fragments so far)."""
        if self.sampling is not None or self.session is None:
            return self.sampling
        if self._live is None:
            self._live = self.session.snapshot(stitch=False)
        return self._live

    def _outlines(self):
        self.outline_set = LY.outlines(self.canvas, self.sampling, self.style)
        if self.sampling.outlines and any(near for _, near in self.hiders.values()) and not self.outline_set.count():
            self.warnings.append("nothing of the model is seen: the models in front of it hide all its outlines")
        for name, strokes in self.outline_set.layers.items():
            if name in self.job.owned_layers():
                self.layers[name] = strokes
        self._next()

    def _region(self):
        """The region of the PLACE_STROKES request (None: the whole model, or none)."""
        return next((r.region for r in self.requests if r.kind == PLACE_STROKES), None)

    def marks(self, layer):
        """The marks a stroke layer ("hatching", "short", "stipples") starts from, made
        once per illustration (after its initialisation): a stroke's ``mark`` is one of
        their keys (a flock's members' and the cross-hatching's are derived from them)."""
        return self._marks(layer)

    def _marks(self, layer):
        """The marks a stroke layer starts from, made once per model (kept with its
        evaluator: the next frame's takes them where its model is the same)."""
        key = ("marks", layer, self.job.seed, self.canvas.unit)
        if key not in self.ev.memo:
            self.ev.memo[key] = LY.marks_of(self.canvas, layer, owners(self.ev), self.job.seed)
        return self.ev.memo[key]

    def continuation(self):
        """What this illustration leaves the next frame's (pipeline.continuation), once it
        ran to its end (None before, or after a stop)."""
        if not self.finished or self.stopping or self.ev is None:
            return None
        traced = "sampling" in self.completed and self.session is not None
        return Continuation(self.ev, self.session.continuation() if traced else None,
                            LY.occluder_evaluators(self.canvas.sight))

    def _stroke_layer(self, layer, parts, draw, marks=None, **kw):
        """One part of a stroke layer per step (the parts listed at the layer's first
        step, from the marks of ``marks``); the layer's stage ends with its last part."""
        if self._parts is None:
            self._parts = parts(self.canvas, self.sampling, self._marks(marks) if marks else None, self.style,
                                self._region())
            self._part = 0
        strokes = draw(self.canvas, self.sampling, self.style, self._region(), self._parts[self._part], **kw)
        self.layers.setdefault(layer, []).extend(strokes)
        self._part += 1
        if self._part == len(self._parts):
            self._parts = None
            self._next()

    def _line_layer(self, stage, parts, draw, marks=None, keep_lines=False, **kw):
        """A layer of lines spaced on the paper (strokes.hatching) in parts, its lines so
        far kept over them (with ``keep_lines``, the layer's before it too: the
        cross-hatching's ends share the paper with the hatching's), ended at the visible
        outlines."""
        if self._parts is None and not (keep_lines and self._lines is not None):
            self._lines = Placed()
        self._stroke_layer(STYLE_LAYERS[stage], parts, draw, marks, lines=self._lines,
                           outlines=self._drawn_lines(), seed=self.job.seed, **kw)

    def _hatching(self, cross=False):
        seed = self.job.seed

        def parts(cv, sampling, marks, st, region):
            return LY.map_parts(cross)(cv, sampling, marks, st, region, seed)
        self._line_layer("hatching", parts, LY.hatching, "hatching", keep_lines=cross, cross=cross)

    def _cross_hatching(self):
        self._hatching(cross=True)

    def _chains(self):
        self._line_layer("chains", LY.chains_parts, LY.chains)

    def _short(self):
        self._line_layer("short", LY.ordered_parts("short"), LY.short, "short")

    def _stipples(self):
        if self._parts is None:
            self._dots = Placed()          # the layer's dots drawn so far, over its parts
        self._stroke_layer(STYLE_LAYERS["stipples"], LY.mark_parts, LY.stipples, "stipples", dots=self._dots,
                           lines=self._drawn_lines(), seed=self.job.seed)

    def _drawn_lines(self):
        """The visible outlines the stroke layers keep clear of and end at: this run's, as
        the ink keeps them (single precision: so a look drawn at once and one drawn from
        the outlines already in the ink are the same), or the job's own (the ink's)."""
        if self.outline_set is None:
            return self.job.lines
        if self._lines_kept is None:
            self._lines_kept = [replace(s, points=s.points.astype(np.float32).astype(float),
                                        radius=s.radius.astype(np.float32).astype(float))
                                for name in LAYER_OF_KIND.values() for s in self.outline_set.layers.get(name, ())]
        return self._lines_kept

    def _single(self):
        cursor = [r.cursor for r in self.requests if r.kind == SINGLE_STROKE][0]
        stroke = LY.single_stroke(self.canvas, self.style, cursor, self.job.seed)
        if stroke is None:
            self.warnings.append("the start point is not near the surface: no stroke")
        self.layers.setdefault(SINGLE_LAYER, []).extend([stroke] if stroke is not None else [])
        self._next()

    # --- results ----------------------------------------------------------------------
    def progress(self):
        """The progress figures now (the fraction never goes down)."""
        n = len(self.stages)
        strokes = [s for s in self.stages if s not in SHARES]

        def share(s):
            return SHARES.get(s, SHARES["strokes"] / max(len(strokes), 1))
        done_shares = sum(share(s) for s in self.completed)
        if self._parts:
            done_shares += share(self.stage) * self._part / len(self._parts)
        current = self._current()
        if self.stage == "sampling" and current is not None:
            done_shares += share("sampling") * self._sampled(current)
        self._fraction = max(self._fraction, min(1.0, done_shares / sum(share(s) for s in self.stages)))
        outs = current.outlines if current is not None else []
        figures = current.progress if current is not None else {}
        return Progress(fraction=self._fraction, stage=self.stage, stage_index=min(self.at, n), stages=n,
                        iterations=figures.get("iterations", 0), outlines=len(outs),
                        outline_length=figures.get("outline_length", 0.0), seconds=self._seconds)

    @staticmethod
    def _sampled(sampling):
        """The share of the sampling done: half the share of the blackboard's seeds taken
        so far, half the share of the tasks started that have ended (the agents take
        most seeds at once and then trace them over many iterations)."""
        p = sampling.progress
        seeds = p["seeds_taken"] / p["seeds"] if p.get("seeds") else 0.0
        tasks = p["tasks_ended"] / p["tasks_started"] if p.get("tasks_started") else 0.0
        return 0.5 * (seeds + tasks)

    def result(self):
        """What is made so far as a :class:`Result` (strokes, the layers the job owns and
        adds to, progress, warnings)."""
        j = self.job
        out = StrokeSet()
        owned = self._owned_now()
        current = self._current()
        if self.outline_set is None and current is not None and "outlines" in self.stages:
            # still tracing: the outlines found so far as they are (hidden lines go at the end)
            r = self.canvas.radius(self.style)
            for name, strokes in StrokeSet.from_outlines(current.outlines, r).layers.items():
                if name in owned:
                    out.layers[name] = strokes
        for name, strokes in self.layers.items():
            out.layers[name] = list(strokes)
        return Result(out, owned, j.appended_layers(), self.progress(), list(self.warnings),
                      done=self.finished and not self.stopping, stopped=self.stopping, region=self._region(),
                      eye=self.eye, centre=self.centre, model=self.model_key,
                      made=None if self.model_key is None else j.making(self.model_key),
                      hiders=self.hiders)

    def _owned_now(self):
        """The layers the result replaces now: those of the stages begun (a stopped run
        replaces no layer it did not reach; a finished one every layer it owns)."""
        begun = set(self.completed) | ({self.stage} if self._parts is not None or self.stage == "outlines" else set())
        if self.stage == "sampling" and "outlines" in self.stages:
            begun.add("outlines")              # the outlines found so far are shown while tracing
        layers = set()
        if "outlines" in begun:
            layers |= {LAYER_OF_KIND[k] for k in self.job.settings.kinds}
        layers |= {STYLE_LAYERS["hatching" if s == "cross-hatching" else s] for s in begun if s in STROKE_STAGES}
        return tuple(x for x in self.owned if x in layers)
