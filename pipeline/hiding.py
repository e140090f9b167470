"""What hides a model's lines besides itself, as a drawing records it: for each other
model of the scene (by its name), the key of that model standing where it stood, and
whether it stood between the eye and the drawn model. A drawing is out of date when a
model that stood between has moved, changed or gone, or when another has come between
(:func:`changed`); one that moved elsewhere, away from the view of the drawn model,
hid nothing and hides nothing."""
import hashlib
import json

import numpy as np

from ..blackboard.polygonise import surface_box
from ..model import key_of
from .framing import bounds
from .job import placed


def place_key(model_key, matrix):
    """The key of a model (``model_key``, its model.fingerprint) standing where
    ``matrix`` (4x4, from the drawn model's coordinates into its own) puts it."""
    return hashlib.sha1(repr(placed(model_key, matrix)).encode("utf-8")).hexdigest()[:16]


def between(eye, sphere, other):
    """Whether the sphere ``other`` ((centre, radius)) can hide part of ``sphere`` seen
    from ``eye``: their discs overlap in the view, and the other's near side is nearer
    the eye than the sphere's far side (an eye inside either: it can)."""
    (c, r), (c2, r2) = sphere, other
    d, d2 = float(np.linalg.norm(c - eye)), float(np.linalg.norm(c2 - eye))
    if d <= r or d2 <= r2:
        return True
    cos = float(np.dot(c - eye, c2 - eye)) / (d * d2)
    apart = np.arccos(np.clip(cos, -1.0, 1.0))
    return bool(apart <= np.arcsin(r / d) + np.arcsin(r2 / d2) and d2 - r2 < d + r)


def sphere_of(box, back):
    """The sphere round a box (lo, hi) of another model's coordinates, in the drawn
    model's (``back``: the 4x4 matrix from the other's coordinates into the drawn's)."""
    lo, hi = box
    corners = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])])
    back = np.asarray(back, float)
    P = corners @ back[:3, :3].T + back[:3, 3]
    centre = P.mean(axis=0)
    return centre, float(np.linalg.norm(P - centre, axis=1).max())


def named(items):
    """``items`` ((name, value) each) as a dict, a name met again taking '#2', '#3', ...
    after it in their order (the scene's trees are always taken in one order)."""
    out = {}
    for name, value in items:
        key, k = name, 1
        while key in out:
            k += 1
            key = f"{name}#{k}"
        out[key] = value
    return out


def hiders(ev, eye, sight):
    """{name: (key, between)} of the other models of ``sight`` (strokes.visibility.Sight,
    or None: no other) for the model ``ev`` seen from ``eye`` (model coordinates)."""
    if sight is None or not sight.others:
        return {}
    drawn = bounds(ev)
    items = []
    for other, M in sight.others:               # (a job's occluder matrices are checked invertible)
        box = surface_box(other)
        near = box is not None and between(np.asarray(eye, float), drawn, sphere_of(box, np.linalg.inv(M)))
        items.append((other.model.name, (place_key(key_of(other), M), near)))
    return named(items)


def encoded(hiders):
    """:func:`hiders` as one string, as a drawing keeps it (names of any length)."""
    return json.dumps({name: [key, bool(near)] for name, (key, near) in hiders.items()}, sort_keys=True)


def decoded(text):
    """The hiders an :func:`encoded` string holds."""
    return {name: (key, bool(near)) for name, (key, near) in json.loads(text).items()}


def changed(recorded, current):
    """Whether a drawing that recorded ``recorded`` ({name: (key, between)}, as
    :func:`hiders` gives) is out of date among the models ``current`` ({name: (key,
    between now)}): one that stood between has moved, changed or gone, or one now
    between was not there (or stood elsewhere) when it was drawn."""
    for name, (key, was) in recorded.items():
        now = current.get(name)
        if (now is None or now[0] != key) and (was or (now is not None and now[1])):
            return True
    return any(near and name not in recorded for name, (_, near) in current.items())
