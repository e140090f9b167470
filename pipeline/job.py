"""What to illustrate: a :class:`Job` (a compiled model, a view, a light, a style, the
requests, a seed and the sampling settings), plain data checked once, and the layers
each request draws."""
import hashlib
from dataclasses import dataclass, field, replace

import numpy as np

from ..agents import Region, Settings
from ..blackboard.view import View
from ..model import Evaluator, Model, fingerprint
from ..strokes.data import LAYER_OF_KIND, STROKE_LAYERS, Stroke
from ..strokes.style import STROKE_SWITCHES, Style

OUTLINES, PLACE_STROKES, SINGLE_STROKE, FIND_FEATURES = REQUESTS = (
    "OUTLINES", "PLACE_STROKES", "SINGLE_STROKE", "FIND_FEATURES")
# the stroke layers each style switch draws on (strokes.data.LAYERS)
STYLE_LAYERS = dict(zip(STROKE_SWITCHES, STROKE_LAYERS))
SINGLE_LAYER = "Single Strokes"
LIGHT_DIGITS = 9            # decimals of a light's direction or position that tell two drawings apart


def placed(model_key, matrix):
    """A model (its key, model.fingerprint) standing where ``matrix`` puts it, as drawings
    tell such models apart: the key and the matrix rounded to LIGHT_DIGITS."""
    return model_key, np.round(np.asarray(matrix, float), LIGHT_DIGITS).tolist()


class JobError(ValueError):
    """A job that cannot be illustrated; the message names what is wrong."""


@dataclass(frozen=True)
class Around:
    """A region to be made once the model's size is known: a sphere around ``centre``,
    its radius ``size`` times the radius of the model's surface box."""
    centre: tuple
    size: float

    def check(self):
        c = np.asarray(self.centre, float)
        if c.shape != (3,) or not np.all(np.isfinite(c)):
            raise JobError(f"a region's centre must be three finite numbers, got {self.centre!r}")
        if not (isinstance(self.size, (int, float)) and np.isfinite(self.size) and self.size > 0):
            raise JobError(f"a region's size must be a positive number, got {self.size!r}")

    def region(self, radius):
        return Region(sphere=(np.asarray(self.centre, float), float(self.size) * radius))


@dataclass(frozen=True)
class Request:
    """One of MASSRIS's Table 1 requests: trace the feature outlines (OUTLINES), find
    features in a region for more detail (FIND_FEATURES), place the style's strokes in a
    region (PLACE_STROKES), or one stroke from a point near the surface (SINGLE_STROKE,
    from ``cursor``). A region is an agents.Region or an :class:`Around`; no region: the
    whole model."""
    kind: str
    region: Region = None
    cursor: tuple = None

    def check(self):
        if self.kind not in REQUESTS:
            raise JobError(f"unknown request {self.kind!r}; one of {', '.join(REQUESTS)}")
        if isinstance(self.region, Around):
            self.region.check()
        elif self.region is not None and not isinstance(self.region, Region):
            raise JobError(f"a request's region must be an agents.Region or a pipeline.Around, got "
                           f"{type(self.region).__name__}")
        if self.kind == SINGLE_STROKE:
            c = np.asarray(self.cursor if self.cursor is not None else (np.nan,) * 3, float)
            if c.shape != (3,) or not np.all(np.isfinite(c)):
                raise JobError(f"a single stroke needs a start point of three finite numbers, got {self.cursor!r}")


@dataclass(frozen=True)
class Job:
    """Everything an illustration depends on. ``model``: a compiled model (an
    model.Evaluator) or a model.Model (the illustration compiles it, on its worker);
    ``view``: where the eye is (blackboard.View with an eye; None: a three-quarter view
    framing the model); ``light``: a direction towards the light, or ``light_at``: a
    point light's position (the light comes from there to the model's centre), neither:
    from the viewer's upper left; ``seed``: the seed of every random
    choice (the settings' seed is replaced by it); ``seconds``: a time budget for the
    agents' iterations (None: run to the end; a budget makes the outlines depend on the
    machine's speed); ``occluders``: the other solids of the scene that can hide the
    model's lines, (model, matrix) each: a model.Model or model.Evaluator, and the 4x4
    matrix taking a point of this model's coordinates into that one's; ``lines``: the
    visible outlines drawn already (strokes.data.Stroke, in the model's coordinates)
    that the stroke layers end at and keep clear of, where the job draws none itself (they are drawn from
    what the job is made from: no part of :meth:`making`)."""
    model: object
    view: View = None
    light: tuple = None
    style: Style = field(default_factory=Style)
    requests: tuple = (Request(OUTLINES),)
    seed: int = 0
    settings: Settings = field(default_factory=Settings)
    seconds: float = None
    light_at: tuple = None
    occluders: tuple = ()
    lines: tuple = ()

    def checked(self):
        """This job, checked (JobError naming the first bad part)."""
        if not self.requests:
            raise JobError("nothing requested")
        for r in self.requests:
            if not isinstance(r, Request):
                raise JobError(f"requests must be pipeline.Request values, got {type(r).__name__}")
            r.check()
        kinds = [r.kind for r in self.requests]
        if len(set(kinds)) != len(kinds):
            raise JobError(f"each request at most once in a job, got {', '.join(kinds)}")
        if self.view is not None:
            if not isinstance(self.view, View) or self.view.eye is None:
                raise JobError("the view must be a blackboard.View with an eye position")
            if np.shape(self.view.eye) != (3,) or not np.all(np.isfinite(self.view.eye)):
                raise JobError(f"the eye must be three finite numbers, got {self.view.eye.tolist()}")
        if self.light is not None and self.light_at is not None:
            raise JobError("a light direction or a light position, not both")
        if self.light is not None:
            L = np.asarray(self.light, float)
            if L.shape != (3,) or not np.all(np.isfinite(L)) or not np.linalg.norm(L) > 0:
                raise JobError(f"the light direction must be three finite numbers, not all zero, got {self.light!r}")
        if self.light_at is not None and (np.shape(self.light_at) != (3,) or not np.all(np.isfinite(self.light_at))):
            raise JobError(f"the light position must be three finite numbers, got {self.light_at!r}")
        if isinstance(self.seed, bool) or not isinstance(self.seed, (int, np.integer)) or not 0 <= self.seed < 2**63:
            raise JobError(f"seed must be a whole number from 0, got {self.seed!r}")
        if self.seconds is not None and not (isinstance(self.seconds, (int, float)) and self.seconds > 0
                                             and np.isfinite(self.seconds)):
            raise JobError(f"the time budget must be a positive number of seconds, got {self.seconds!r}")
        try:
            self.style.check()
            self.settings.check()
        except ValueError as e:
            raise JobError(str(e)) from None
        if not isinstance(self.model, (Evaluator, Model)):
            raise JobError(f"the model must be a model.Model or a model.Evaluator, got {type(self.model).__name__}")
        if not all(isinstance(s, Stroke) for s in self.lines):
            raise JobError("the lines drawn already must be strokes.data.Stroke values")
        for k, occluder in enumerate(self.occluders):
            if not (isinstance(occluder, tuple) and len(occluder) == 2 and isinstance(occluder[0], (Evaluator, Model))):
                raise JobError(f"occluder {k} must be a (model, matrix) pair, got {occluder!r:.80}")
            M = np.asarray(occluder[1], float)
            if M.shape != (4, 4) or not np.all(np.isfinite(M)) or np.linalg.cond(M[:3, :3]) > 1e12:
                raise JobError(f"occluder {k}'s matrix must be an invertible 4x4 of finite numbers")
        # one seed: the job's (the sampling's explorers and every stroke layer derive theirs from it)
        return replace(self, requests=tuple(self.requests), seed=int(self.seed), lines=tuple(self.lines),
                       settings=replace(self.settings, seed=int(self.seed)), style=self.style.rounded())

    @property
    def kinds(self):
        return tuple(r.kind for r in self.requests)

    def wants_outline_layers(self):
        """Whether the job draws the outline layers (an outline request)."""
        return bool({OUTLINES, FIND_FEATURES} & set(self.kinds))

    def wants_outlines(self):
        """Whether the agents trace outlines: for the outline layers, or for the strokes
        started from them."""
        return self.wants_outline_layers() or (PLACE_STROKES in self.kinds and self.style.chains)

    def stroke_switches(self):
        """The style's stroke layers a PLACE_STROKES request draws."""
        return self.style.stroke_switches() if PLACE_STROKES in self.kinds else ()

    def making(self, model_key):
        """A key of what this job's drawing is made from besides the eye: the model (its
        ``model_key``, model.fingerprint), the light, the style, the seed, the sampling
        settings and the occluders (their models' keys and places). Two checked jobs with
        one key, seen from one eye, draw alike."""
        light = [None if v is None else [round(float(x), LIGHT_DIGITS) for x in v] for v in (self.light, self.light_at)]
        hiding = [placed(fingerprint(m.model if isinstance(m, Evaluator) else m), M) for m, M in self.occluders]
        text = repr((model_key, light, self.style, self.seed, self.settings) + ((hiding,) if hiding else ()))
        return hashlib.sha1(text.encode("utf-8")).hexdigest()[:16]

    def owned_layers(self):
        """The layers this job's result replaces as a whole, even where it draws nothing
        on one (running a request again replaces what it made): the outline layers of an
        outline request, the layers of the style's strokes a PLACE_STROKES request draws.
        Every other layer is left as it is."""
        out = []
        if self.wants_outline_layers():
            out += [LAYER_OF_KIND[k] for k in self.settings.kinds]
        out += [STYLE_LAYERS[k] for k in self.stroke_switches()]
        return tuple(dict.fromkeys(out))

    def appended_layers(self):
        """The layers this job's result adds to (a single stroke joins the ones before)."""
        return (SINGLE_LAYER,) if SINGLE_STROKE in self.kinds else ()
