"""What each ink layer's drawing on a frame was drawn for, kept on the ink object
itself (ID properties: saved, undone and copied with it): the viewpoint (every layer's
hidden lines are removed for one eye, and silhouettes, suggestive contours and apparent
ridges are that eye's) and the model (its key, model.fingerprint). A layer drawn for
another viewpoint (pipeline.framing.same_view) or another model than the rest of the
drawing does not fit it: a request tells which layers it did not redraw are so. And
all the drawing was made from (pipeline.Job.making): a render uses a drawing shown on
a frame only where it was made from all the frame's job is, for the very same eye.
And the other models that hid its lines (pipeline.hiding): when one of them that stood
between has moved or changed, or another has come between, the drawing is out of date."""
import numpy as np

from ..pipeline.framing import same_view
from ..pipeline.hiding import changed, decoded, encoded

KEY = "blobtree_ink_views"      # the ID property: "layer@frame" -> the eye (model coordinates), or MIXED
MODELS = "blobtree_ink_models"  # the ID property: "layer@frame" -> the model's key, or MIXED
MADE = "blobtree_ink_made"      # the ID property: "layer@frame" -> all it was made from but the eye
                                # (pipeline.Job.making), or MIXED
HIDERS = "blobtree_ink_hiders"  # the ID property: "layer@frame" -> the other models that hid its lines
                                # (pipeline.hiding.encoded), or MIXED
SAME_EYE = 1e-9                 # eyes this close (a share of their distance from the origin, at least 1) are one
MIXED = "mixed"                 # a drawing with strokes drawn for several eyes or models (a region redrawn)
VIEWPOINT, MODEL = "viewpoint", "model"     # why a drawing does not fit (:func:`unfit`)


def _key(layer, frame):
    return f"{layer}@{int(frame)}"


def record(obj, layers, frame, eye, centre, region=None, model=None, made=None, hiders=None):
    """Remember that ``layers`` of the ink object were drawn on ``frame`` for ``eye``
    (the model's ``centre`` tells two eyes apart; both in the model's coordinates), the
    model of key ``model``, all that is ``made`` (the job's key) and the other models
    that hid its lines (``hiders``: pipeline.hiding.hiders). A drawing redrawn only in
    a ``region`` for another eye or model than its own, or over strokes drawn before
    models were kept, holds both: it is mixed from then on."""
    if eye is None or centre is None or not layers:
        return
    hiders = None if hiders is None else encoded(hiders)
    for prop in (KEY, MODELS, MADE, HIDERS):
        if prop not in obj:
            obj[prop] = {}
    views = obj[KEY]                    # set in place: a bake's many frames are not copied each frame
    for layer in layers:
        key = _key(layer, frame)
        old = views.get(key)
        if region is not None and old is not None and not _fits(old, eye, centre):
            views[key] = MIXED
        else:
            views[key] = [float(v) for v in eye]
        for prop, value in ((MODELS, model), (MADE, made), (HIDERS, hiders)):
            if value is None:
                continue
            kept = obj[prop].get(key, MIXED if old is not None else None)     # (drawn, none kept: unknown)
            obj[prop][key] = MIXED if region is not None and kept is not None and _differ(prop, kept, value) else value


def _differ(prop, kept, value):
    """Whether a region redrawn for ``value`` leaves the drawing mixed with strokes drawn
    for ``kept``: other models' moves that hid nothing then or now do not count."""
    if prop != HIDERS or kept == MIXED:
        return kept != value
    return changed(decoded(kept), decoded(value))


def forget(obj, layers, frame):
    """Forget what ``layers``' drawings on ``frame`` were drawn for (they were cleared)."""
    for prop in (KEY, MODELS, MADE, HIDERS):
        kept = obj.get(prop)
        for layer in layers if kept is not None else ():
            kept.pop(_key(layer, frame), None)


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


def other_hiders(obj, layers, frame, current):
    """Those of ``layers`` whose drawing shown on ``frame`` has strokes whose hiders are
    out of date (pipeline.hiding.changed) among those ``current(eye)`` gives ({name:
    (key, between now)} for the drawing's eye, or None: not known); a drawing with none
    kept, or mixed, counts as fitting."""
    kept = obj.get(HIDERS, {}) if obj is not None else {}
    eyes = obj.get(KEY, {}) if obj is not None else {}
    out, now = [], {}
    for name, key, strokes in _shown(obj, layers, frame):
        rec, eye = kept.get(key), eyes.get(key)
        if not strokes or rec is None or rec == MIXED or eye is None or isinstance(eye, str):
            continue
        eye = tuple(float(v) for v in eye)
        if eye not in now:                    # (the layers of one drawing share their eye)
            now[eye] = current(eye)
        if now[eye] is not None and changed(decoded(rec), now[eye]):
            out.append(name)
    return out


def holds(obj, layers, frame, eye, made):
    """Whether each of ``layers`` shows a drawing on ``frame`` (the key at or before it)
    kept as drawn for this very ``eye`` (:func:`drawn_at`) and from all that is ``made``
    (pipeline.Job.making): a render can use it as it is."""
    shown = list(_shown(obj, layers, frame))
    kept = obj.get(MADE, {}) if shown else {}
    return len(shown) == len(layers) > 0 and all(kept.get(key) == made for _, key, _ in shown) and \
        drawn_at(obj, layers, frame, eye, strict=True)


def drawn_at(obj, layers, frame, eye, strict=False):
    """Whether the drawings ``layers`` show on ``frame`` were drawn for this very ``eye``
    (within SAME_EYE): those with strokes, a drawing with no eye kept counting as
    drawn there; with ``strict``, every one, and each must have its eye kept."""
    views = obj.get(KEY, {}) if obj is not None else {}
    eye = np.asarray(eye, float)
    near = SAME_EYE * max(1.0, float(np.linalg.norm(eye)))
    for _, key, strokes in _shown(obj, layers, frame):
        if not (strokes or strict):
            continue
        kept = views.get(key, MIXED if strict else None)
        if kept is None:
            continue
        if isinstance(kept, str) or float(np.linalg.norm(np.asarray(kept[:3], float) - eye)) > near:
            return False
    return True


def shown_frame(layer, frame):
    """The layer's key shown on ``frame`` (its last at or before it: Grease Pencil holds
    a drawing until the next key), or None before its first."""
    keys = [f for f in layer.frames if f.frame_number <= frame]
    return max(keys, key=lambda f: f.frame_number) if keys else None


def _shown(obj, layers, frame):
    """(layer, its record's key, its stroke count) of each of ``layers`` that shows a
    drawing on ``frame`` (the key at or before it)."""
    if obj is None or obj.type != "GREASEPENCIL":
        return
    for name in layers:
        layer = obj.data.layers.get(name)
        shown = None if layer is None else shown_frame(layer, frame)
        if shown is not None:
            yield name, _key(name, shown.frame_number), len(shown.drawing.strokes)


def _fits(kept, eye, centre):
    """Whether a drawing's kept viewpoint (an eye, or MIXED) is one that sees the model
    like ``eye``."""
    return not isinstance(kept, str) and same_view(np.asarray(kept[:3], float), eye, centre)
