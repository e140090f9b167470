"""Make the repository's pure packages importable as ``blobtree_ink.*`` without bpy.

The repository root is the extension package, whose ``__init__`` needs bpy. Scripts
and core tests register a bare package object pointing at the root instead, so that
``import blobtree_ink.model`` runs only the numpy-only code.
"""
import os
import sys
import types

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def install(name="blobtree_ink"):
    mod = sys.modules.get(name)
    if mod is None:
        mod = types.ModuleType(name)
        mod.__path__ = [REPO]
        mod.__file__ = os.path.join(REPO, "__init__.py")
        mod.__package__ = name
        sys.modules[name] = mod
    return mod
