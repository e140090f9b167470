"""Tolerances, named once and used everywhere.

Field tolerances bound |f - iso| and scale with the iso value (field values scale with
it): :func:`field_tol` gives ``rel * max(1, |iso|)``. Length tolerances are fractions
of the model's size (``Evaluator.scale``, the diagonal of its support box).

- CONVERGED: a projection onto the surface stops; below it a point is on the surface
  to rounding.
- ON_SURFACE: a point the agents found (an outline point, a seed, a bisection's trial
  point, a probe on a thin part, a wall of a subtracted part) lies on the surface.
  Newton's projection reaches CONVERGED in a few steps where the field is smooth; a
  point above ON_SURFACE after them sits where it cannot converge (beside a sharp
  wedge, on a flat core) and is not used.
- TRIAL: a bisection's trial point, after its two Newton steps, is near enough to
  the surface for the sign of its quantity and may move a bracket end (near a sharp
  wedge's edge Newton can stall between the sheets); a crossing left on such a point
  is projected the rest of the way.
- CROSSING: a fine grid edge's crossing (the subdivided voxels') stops its regula
  falsi here; the feature seeds built from those crossings are projected again.
- NEAR_SURFACE: a start (an explorer's or a smarticle's position, a polygon vertex)
  is near enough to the surface to work from; it is projected again as it moves.
- OUTLINE: where an outline point is located, as a fraction of the model's size
  (``agents.Settings.tolerance``'s default): the last Newton step of a corrector, the
  width a smooth bracket is bisected down to. A crease bracket stops at
  sqrt(OUTLINE x its length), where the tangent planes' meeting point is within about
  OUTLINE of the crease (agents.bisection).
"""
import numpy as np

CONVERGED = 1e-14
ON_SURFACE = 1e-9
TRIAL = 1e-8
CROSSING = 1e-11
NEAR_SURFACE = 1e-6
OUTLINE = 1e-8


def field_tol(iso, rel):
    """The |f - iso| bound of a relative tolerance at this iso value."""
    return rel * max(1.0, abs(float(iso)))


def on_surface(f, iso, rel=ON_SURFACE):
    """Whether field values f lie on the iso-surface within ``rel`` (a boolean array)."""
    return np.abs(np.asarray(f) - iso) <= field_tol(iso, rel)
