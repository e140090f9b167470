"""Plain stroke data and hidden-line removal (pure, numpy only)."""
from .data import LAYERS, Stroke, StrokeSet  # noqa: F401
from .visibility import split_visible, visible  # noqa: F401
