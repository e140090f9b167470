"""The one illustration pipeline (pure, numpy only): a job in, plain strokes by layer
out, through a resumable stepper that every path drives (the modal and background
operators and the command line)."""
from .continuation import Continuation  # noqa: F401
from .framing import (MARGIN, NothingToDraw, bounds, default_light, inside, line_radius, ortho_fit,  # noqa: F401
                      perspective_fit, same_view, three_quarter_eye, view_eye)
from .illustration import Illustration  # noqa: F401
from .job import (FIND_FEATURES, OUTLINES, PLACE_STROKES, REQUESTS, SINGLE_STROKE, Around, Job, JobError,  # noqa: F401
                  Request)
from .result import Progress, Result  # noqa: F401
from .runner import Runner, RunnerError  # noqa: F401
