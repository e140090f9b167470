"""Undo while an illustration or a bake runs. Blender's undo would restore the data as
it was before the step ahead of the run (the run is no undo step until it ends): the
model itself, imported or edited just before, would go, and the run would go on
writing into data that is no more. So an undo key pressed over a run stops the run
as Esc does, keeping what it drew as one undo step that the next undo takes back
(:func:`undo_key`, with the keys of :func:`undo_keys`); and an undo that happens
anyway (from the Edit menu, or a script) ends the run at its next tick with nothing
written (:func:`undos`: the run compares the count with the one it started with)."""
import bpy

from ..blobtree_nodes import handlers

UNDO_OPERATORS = ("ed.undo", "ed.redo", "ed.undo_history")
DEFAULT_KEYS = (("Z", True, False), ("Z", True, True))     # (key, Ctrl, Shift): Blender's own undo and redo

_count = [0]                  # undos and redos since the extension started


def undos():
    """How many undos and redos have happened (a run that sees this change was undone)."""
    return _count[0]


@bpy.app.handlers.persistent
def _undone(*_args):
    _count[0] += 1


def undo_keys(context):
    """The keys (and mouse buttons) the keymap in use binds to undo and redo, (type,
    ctrl, shift, alt, oskey, hyper) each, a modifier 1 held, 0 not, -1 either (Blender's
    Ctrl+Z and Ctrl+Shift+Z where it binds none)."""
    wm = getattr(context, "window_manager", None)
    config = wm.keyconfigs.user if wm is not None else None
    out = []
    for km in (config.keymaps if config is not None else ()):
        for kmi in km.keymap_items:
            if kmi.idname in UNDO_OPERATORS and kmi.active and kmi.map_type in ("KEYBOARD", "MOUSE"):
                out.append((kmi.type, int(kmi.ctrl), int(kmi.shift), int(kmi.alt), int(kmi.oskey),
                            int(getattr(kmi, "hyper", -1))))
    return out or [(k, int(c), int(s), 0, 0, -1) for k, c, s in DEFAULT_KEYS]


def undo_key(event, keys):
    """Whether ``event`` is a press of one of ``keys`` (:func:`undo_keys`)."""
    if event.value != "PRESS":
        return False
    held = (event.ctrl, event.shift, event.alt, event.oskey, getattr(event, "hyper", False))
    return any(event.type == k[0] and all(m == -1 or bool(m) == h for m, h in zip(k[1:], held)) for k in keys)


HANDLERS = ((bpy.app.handlers.undo_pre, _undone), (bpy.app.handlers.redo_pre, _undone))


def register():
    handlers.attach(HANDLERS)


def unregister():
    handlers.detach(HANDLERS)
