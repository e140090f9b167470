"""The blobtree-ink command line (pure parts; `render` reaches Blender lazily)."""
from .main import main  # noqa: F401
