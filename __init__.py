"""BlobTree Ink: model skeletal implicit surfaces in a node editor and illustrate them
in pen and ink as Grease Pencil (a Blender extension)."""
import bpy

from . import blobtree_nodes, cli, operators
from .cli.main import register_renderer, unregister_renderer
from .operators import render_cli

modules = (blobtree_nodes, operators)


def _cli_command(argv):
    return cli.main(argv)


_cli_handle = None
CLI_COMMAND = "blobtree_ink"


def register():
    global _cli_handle
    for m in modules:
        m.register()
    register_renderer(render_cli.render)
    # Blender only accepts a Python identifier as a command id, so the command is
    # `blender -c blobtree_ink ...` (the repository script is still ./blobtree-ink).
    _cli_handle = bpy.utils.register_cli_command(CLI_COMMAND, _cli_command)


def unregister():
    global _cli_handle
    if _cli_handle is not None:
        bpy.utils.unregister_cli_command(_cli_handle)
        _cli_handle = None
    unregister_renderer()
    for m in reversed(modules):
        m.unregister()
