"""Grease Pencil output (Blender layer)."""
from .compat import grease_pencil_data  # noqa: F401
