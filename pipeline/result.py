"""What an illustration hands out: its :class:`Result` (plain strokes by layer, what
they replace, and what they were drawn for) and its :class:`Progress`."""
from dataclasses import dataclass, field

import numpy as np

from ..strokes.data import StrokeSet


@dataclass
class Progress:
    """Figures of a run for the status bar: ``fraction`` (0..1) only goes up; the stage
    being worked on and its number among the stages; the agents' iteration and outline
    figures."""
    fraction: float = 0.0
    stage: str = "init"
    stage_index: int = 0
    stages: int = 1
    iterations: int = 0
    outlines: int = 0
    outline_length: float = 0.0
    seconds: float = 0.0


@dataclass
class Result:
    """Plain strokes by layer: ``owned`` layers are replaced as a whole by the result's
    (also where it has none on one; with a ``region``, the owned stroke layers' strokes
    in that region), ``appended`` ones are added to; the others are not the job's.
    ``done``: the run reached its end (not stopped)."""
    strokes: StrokeSet
    owned: tuple
    appended: tuple
    progress: Progress
    warnings: list = field(default_factory=list)
    done: bool = False
    stopped: bool = False
    region: object = None      # where the owned stroke layers were drawn (None: the whole model): only
                               # their strokes there are replaced
    eye: np.ndarray = None     # the eye it was drawn for and the model's centre (model coordinates),
    centre: np.ndarray = None  # once known (framing.same_view)
    model: str = None          # the model's key (model.fingerprint), once known
    made: str = None           # the key of all it is made from but the eye (Job.making), once known
    hiders: dict = None        # the other models that hid its lines (pipeline.hiding.hiders), once known
