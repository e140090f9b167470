"""The viewpoint each ink layer's drawing on a frame was drawn for, kept on the ink
object itself (an ID property: saved, undone and copied with it): every layer's hidden
lines are removed for one eye, and silhouettes, suggestive contours and apparent
ridges are that eye's, so a layer drawn for another viewpoint than the rest of the
drawing does not fit it. A request tells which layers it did not redraw were drawn for
another viewpoint (pipeline.framing.same_view)."""
import numpy as np

from ..pipeline.framing import same_view

KEY = "blobtree_ink_views"      # the ID property: "layer@frame" -> eye and model centre (model coordinates)


def _key(layer, frame):
    return f"{layer}@{int(frame)}"


def record(obj, layers, frame, eye, centre):
    """Remember that ``layers`` of the ink object were drawn on ``frame`` for ``eye``
    (the model's ``centre`` with it; both in the model's coordinates)."""
    if eye is None or centre is None:
        return
    views = dict(obj.get(KEY, {}))
    for layer in layers:
        views[_key(layer, frame)] = [float(v) for v in (*eye, *centre)]
    obj[KEY] = views


def seen_from_elsewhere(obj, layers, frame, eye, centre):
    """Of ``layers``, those with strokes on ``frame`` that were drawn for an eye that
    does not see the model like ``eye`` (a layer drawn before its viewpoint was kept
    counts as fitting)."""
    if obj is None or obj.type != "GREASEPENCIL":
        return []
    views = obj.get(KEY, {})
    out = []
    for name in layers:
        layer = obj.data.layers.get(name)
        drawn = [f for f in (layer.frames if layer is not None else []) if f.frame_number == frame]
        if not drawn or not len(drawn[0].drawing.strokes):
            continue
        v = views.get(_key(name, frame))
        if v is not None and not same_view(np.asarray(v[:3]), eye, np.asarray(v[3:])):
            out.append(name)
    return out
