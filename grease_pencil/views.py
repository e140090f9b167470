"""What each ink layer's drawing on a frame was drawn for, kept on the ink object
itself (ID properties: saved, undone and copied with it): the viewpoint (every layer's
hidden lines are removed for one eye, and silhouettes, suggestive contours and apparent
ridges are that eye's) and the model (its key, model.fingerprint). A layer drawn for
another viewpoint (pipeline.framing.same_view) or another model than the rest of the
drawing does not fit it: a request tells which layers it did not redraw are so, and a
render uses a drawing held over from an earlier frame only where it fits that frame."""
import numpy as np

from ..pipeline.framing import same_view

KEY = "blobtree_ink_views"      # the ID property: "layer@frame" -> the eye (model coordinates), or MIXED
MODELS = "blobtree_ink_models"  # the ID property: "layer@frame" -> the model's key, or MIXED
MIXED = "mixed"                 # a drawing with strokes drawn for several eyes or models (a region redrawn)
VIEWPOINT, MODEL = "viewpoint", "model"     # why a drawing does not fit (:func:`unfit`)


def _key(layer, frame):
    return f"{layer}@{int(frame)}"


def record(obj, layers, frame, eye, centre, region=None, model=None):
    """Remember that ``layers`` of the ink object were drawn on ``frame`` for ``eye``
    (the model's ``centre`` tells two eyes apart; both in the model's coordinates) and
    the model of key ``model``. A drawing redrawn only in a ``region`` for another eye
    or model than its own holds both: it is mixed from then on."""
    if eye is None or centre is None or not layers:
        return
    for prop in (KEY, MODELS):
        if prop not in obj:
            obj[prop] = {}
    views, models = obj[KEY], obj[MODELS]      # set in place: a bake's many frames are not copied each frame
    for layer in layers:
        key = _key(layer, frame)
        old = views.get(key)
        if region is not None and old is not None and not _fits(old, eye, centre):
            views[key] = MIXED
        else:
            views[key] = [float(v) for v in eye]
        if model is not None:
            old = models.get(key)
            models[key] = MIXED if region is not None and old is not None and old != model else model


def unfit(obj, layers, frame, eye, centre, model=None):
    """{layer: why} for those of ``layers`` whose drawing shown on ``frame`` (the key at
    or before it) has strokes drawn for another model than the one of key ``model``
    (MODEL; not asked without one), or else for an eye that does not see the model (its
    ``centre``) like ``eye`` (VIEWPOINT). A drawing with nothing kept counts as fitting."""
    out = dict.fromkeys(other_model(obj, layers, frame, model), MODEL) if model is not None else {}
    views = obj.get(KEY, {}) if obj is not None else {}
    for name, key, strokes in _shown(obj, layers, frame):
        if strokes and name not in out and key in views and not _fits(views[key], eye, centre):
            out[name] = VIEWPOINT
    return out


def other_model(obj, layers, frame, model):
    """Those of ``layers`` whose drawing shown on ``frame`` has strokes drawn for another
    model than the one of key ``model`` (a drawing with no model kept counts as its)."""
    models = obj.get(MODELS, {}) if obj is not None else {}
    return [name for name, key, strokes in _shown(obj, layers, frame)
            if strokes and models.get(key) is not None and models[key] != model]


def made_for(obj, layers, frame, model):
    """Whether each of ``layers`` shows a drawing on ``frame`` (the key at or before it)
    kept as drawn for the model of key ``model``."""
    shown = list(_shown(obj, layers, frame))
    models = obj.get(MODELS, {}) if shown else {}
    return len(shown) == len(layers) > 0 and all(models.get(key) == model for _, key, _ in shown)


def seen_alike(obj, layers, frame, eye, centre):
    """Whether each of ``layers`` shows a drawing on ``frame`` kept as drawn for an eye
    that sees the model (its ``centre``) like ``eye``."""
    shown = list(_shown(obj, layers, frame))
    views = obj.get(KEY, {}) if shown else {}
    return len(shown) == len(layers) > 0 and all(key in views and _fits(views[key], eye, centre)
                                                  for _, key, _ in shown)


def _shown(obj, layers, frame):
    """(layer, its record's key, its stroke count) of each of ``layers`` that shows a
    drawing on ``frame`` (the key at or before it)."""
    if obj is None or obj.type != "GREASEPENCIL":
        return
    for name in layers:
        layer = obj.data.layers.get(name)
        keys = [f for f in (layer.frames if layer is not None else []) if f.frame_number <= frame]
        if keys:
            shown = max(keys, key=lambda f: f.frame_number)
            yield name, _key(name, shown.frame_number), len(shown.drawing.strokes)


def _fits(kept, eye, centre):
    """Whether a drawing's kept viewpoint (an eye, or MIXED) is one that sees the model
    like ``eye``."""
    return not isinstance(kept, str) and same_view(np.asarray(kept[:3], float), eye, centre)
