"""The strokes a finished MASSRIS request (Table 1) leaves, from a done session:
OUTLINES and FIND_FEATURES draw the visible outlines; PLACE_STROKES adds the style's
stroke layers (hatching when it names none) inside the region; SINGLE_STROKE adds one
smarticle stroke from a point near the surface (the 3D cursor). Pure: the operator
calls it on its worker thread, the tests directly."""
import dataclasses

import numpy as np
from numpy.random import default_rng    # numpy imports it lazily: here, not in a run's first call

from ..model.tolerances import NEAR_SURFACE, on_surface
from . import layers as L
from . import smarticles as sm
from . import style as ST
from .data import Stroke


def final_strokes(session, request, style, eye, light, line_radius, seed=0, region=None, cursor=None):
    """(StrokeSet, warnings) for a done session."""
    st = style
    if request == "PLACE_STROKES":
        if not (st.hatching or st.stipples or st.chains or st.short):
            st = dataclasses.replace(st, hatching=True)
    else:
        st = dataclasses.replace(st, hatching=False, stipples=False, chains=False, short=False)
        region = None
    strokes = ST.place(session, eye, light, st, default_rng(seed), line_radius, region)
    warnings = []
    if request == "SINGLE_STROKE":
        stroke = single_stroke(session, style, eye, line_radius, cursor)
        if stroke is None:
            warnings.append("the 3D cursor is not near the surface: no stroke")
        else:
            strokes.add("Strokes", stroke)
    return strokes, warnings


def single_stroke(session, style, eye, line_radius, point, max_steps=60):
    """One smarticle stroke from the surface point nearest ``point`` (or None when the
    point is too far from the surface to project onto it)."""
    P, f, g = session.surface.project(np.asarray(point, float).reshape(1, 3))
    if not on_surface(f[0], session.ev.iso, NEAR_SURFACE):
        return None
    field = L.direction_field(style.hatch_field, style.hatch_axis, eye)
    res = sm.run(session.ev, P, field, 0.3 * session.h, style.resolved_weights(),
                 sm.StrokeRules(max_steps=max_steps, stop_on_curvature_sign=False), default_rng(0))
    p = res.paths[0]
    if len(p) < 2:
        return None
    r = line_radius * style.line_width
    return Stroke(p, np.full(len(p), r), np.ones(len(p)))
