"""Blender's app handlers that a module keeps: (handler list, function) pairs, attached
once and detached."""


def attach(pairs):
    for lst, fn in pairs:
        if fn not in lst:
            lst.append(fn)


def detach(pairs):
    for lst, fn in pairs:
        if fn in lst:
            lst.remove(fn)
