"""The viewpoint each ink layer's drawing on a frame was drawn for, kept on the ink
object itself (an ID property: saved, undone and copied with it): every layer's hidden
lines are removed for one eye, and silhouettes, suggestive contours and apparent
ridges are that eye's, so a layer drawn for another viewpoint than the rest of the
drawing does not fit it. A request tells which layers it did not redraw were drawn for
another viewpoint (pipeline.framing.same_view)."""
import numpy as np

from ..pipeline.framing import same_view

KEY = "blobtree_ink_views"      # the ID property: "layer@frame" -> the eye (model coordinates), or MIXED
MIXED = "mixed"                 # a drawing with strokes drawn for several eyes (a request's region redrawn)


def _key(layer, frame):
    return f"{layer}@{int(frame)}"


def record(obj, layers, frame, eye, centre, region=None):
    """Remember that ``layers`` of the ink object were drawn on ``frame`` for ``eye``
    (the model's ``centre`` tells two eyes apart; both in the model's coordinates). A
    drawing redrawn only in a ``region`` for another eye than its own holds both: it
    is mixed from then on."""
    if eye is None or centre is None or not layers:
        return
    if KEY not in obj:
        obj[KEY] = {}
    views = obj[KEY]                    # set in place: a bake's many frames are not copied each frame
    for layer in layers:
        key = _key(layer, frame)
        old = views.get(key)
        if region is not None and old is not None and not _fits(old, eye, centre):
            views[key] = MIXED
        else:
            views[key] = [float(v) for v in eye]


def seen_from_elsewhere(obj, layers, frame, eye, centre):
    """Of ``layers``, those whose drawing shown on ``frame`` (the key at or before it)
    has strokes drawn for an eye that does not see the model (its ``centre``) like
    ``eye``; a drawing with no viewpoint kept counts as fitting."""
    if obj is None or obj.type != "GREASEPENCIL":
        return []
    views = obj.get(KEY, {})
    out = []
    for name in layers:
        layer = obj.data.layers.get(name)
        keys = [f for f in (layer.frames if layer is not None else []) if f.frame_number <= frame]
        if not keys:
            continue
        shown = max(keys, key=lambda f: f.frame_number)
        v = views.get(_key(name, shown.frame_number))
        if len(shown.drawing.strokes) and v is not None and not _fits(v, eye, centre):
            out.append(name)
    return out


def _fits(kept, eye, centre):
    """Whether a drawing's kept viewpoint (an eye, or MIXED) is one that sees the model
    like ``eye``."""
    return not isinstance(kept, str) and same_view(np.asarray(kept[:3], float), eye, centre)
