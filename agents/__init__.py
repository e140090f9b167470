"""Task agents, the manager and the baseline particle system (pure, numpy only)."""
from .region import Region  # noqa: F401
from .outline import Outline  # noqa: F401
from .session import Session, Settings  # noqa: F401
