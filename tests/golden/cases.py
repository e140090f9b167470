"""The golden drawings: three examples in three styles through the pipeline, compared
stroke by stroke with stored references (tests/golden/*.npz) by the core tier.

Regenerate the references after a change that is meant to alter drawings:

    tools/golden

and look at what changed (the command prints each case's differences before it
overwrites the reference)."""
import os

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
EXAMPLES = ("pear", "jug", "heart")
STYLES = ("stippled", "hatched", "short-strokes")
GRID, SEED = 16, 0
TOLERANCE = 2e-3            # nearest-point distances, as a fraction of the model's radius


def path(example, style):
    return os.path.join(HERE, f"{example}-{style}.npz")


def draw(load, example, style):
    """The drawing of a case (strokes_match's plain form) and its model's radius."""
    from blobtree_ink import model as M
    from blobtree_ink import pipeline as PL
    from blobtree_ink.agents import Settings
    from blobtree_ink.blackboard.view import View
    from blobtree_ink.strokes import style as ST
    import strokes_match as SM
    ev = M.Evaluator(load(example))
    centre, radius = PL.bounds(ev)
    eye = PL.three_quarter_eye(centre, radius)
    job = PL.Job(ev, View(eye=eye), PL.default_light(centre, eye), ST.style(style),
                 (PL.Request("OUTLINES"), PL.Request("PLACE_STROKES")), SEED, Settings(resolution=GRID))
    return SM.from_stroke_set(PL.Illustration(job).run().strokes), radius


def load_reference(example, style):
    import strokes_match as SM
    with np.load(path(example, style)) as data:
        return SM.from_npz(data)
