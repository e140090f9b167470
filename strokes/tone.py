"""The tone curve: how much ink the light asks for at a point of the surface, the one
mapping every tone layer (hatching, stipples, short strokes, chains) and the quality
measure (bench/quality.py) share.

The light at a point is Lambert's, max(0, n . L), with L the direction towards the sun,
and 0 where the model itself stands between the point and the sun (a cast shadow,
:func:`cast_shadow`). The tone is the share of the paper the ink should cover there:

    ramp = clip((upper - light) / (upper - lower), 0, 1)
    tone = DARKEST * ((1 - contrast) * FLAT + contrast * ramp)     where light < upper
    tone = 0                                                      where light >= upper

``upper`` is the highlight threshold (a brighter point keeps the white paper), ``lower``
the light below which the ink is at its darkest (form and cast shadows), ``contrast``
(0..1) how much of the tonal range the light spans: 1 follows the light from the
highlight to the full shade, 0 lays one flat tone (FLAT of the darkest) over all that is
not highlight. Hatching reaches a tone by its lines' spacing and width and, past
ONE_LAYER, by a second, crossing layer that ramps in; stipples by their density and size.
"""
import numpy as np

from .visibility import hits

DARKEST = 0.4           # the share of the paper the ink covers at the darkest tone
FLAT = 0.5              # contrast 0: the tone of every point in shade, as a share of DARKEST
ONE_LAYER = 0.28        # the tone the first of two layers reaches (hatching's lines; stipples under short strokes)


def lambert(normals, light_dir):
    """max(0, n . L) per point (``light_dir`` towards the light, any length)."""
    L = np.asarray(light_dir, float)
    L = L / np.linalg.norm(L)
    return np.maximum(0.0, np.asarray(normals, float).reshape(-1, 3) @ L)


def light(sight, P, N, light_dir, reach):
    """The light of points P (n, 3) with outward normals N: Lambert's, and 0 where a solid
    of ``sight`` (strokes.visibility.Sight: the model, and the other models of its scene)
    stands between the point and the sun (a ray marched ``reach`` towards it)."""
    P, N = np.asarray(P, float).reshape(-1, 3), np.asarray(N, float).reshape(-1, 3)
    L = np.asarray(light_dir, float) / np.linalg.norm(light_dir)
    lit = lambert(N, L)
    facing = np.flatnonzero(lit > 0)
    if len(facing):
        towards = P[facing] + float(reach) * L
        shadowed = np.isfinite(hits(sight, P[facing], towards, N[facing]))
        lit[facing[shadowed]] = 0.0
    return lit


class Shadows:
    """Cast shadows of one light on a model, known at nodes (points fixed on the model,
    ``spacing`` apart) and found between them: a point facing the sun whose nodes within
    NEAR spacings (facing it too) all agree takes their answer; one between a shadowed
    and a lit node, or with none near, has its own ray marched (:func:`light`), so a
    shadow's edge is as sharp as a point's own ray."""

    def __init__(self, sight, points, normals, light_dir, reach, spacing):
        self.sight, self.reach = sight, float(reach)
        self.L = np.asarray(light_dir, float) / np.linalg.norm(light_dir)
        P, N = np.asarray(points, float).reshape(-1, 3), np.asarray(normals, float).reshape(-1, 3)
        facing = lambert(N, self.L) > 0
        self.points = P[facing]
        self.dark = light(sight, P[facing], N[facing], self.L, reach) == 0
        self.radius = NEAR * float(spacing)

    def light(self, P, N):
        """Lambert's light of points P with normals N, 0 where they are in a cast shadow."""
        from ..blackboard.cells import pairs_within
        P, N = np.asarray(P, float).reshape(-1, 3), np.asarray(N, float).reshape(-1, 3)
        lit = lambert(N, self.L)
        facing = np.flatnonzero(lit > 0)
        if len(facing) == 0:
            return lit
        i, j = pairs_within(P[facing], self.points, self.radius)
        n = len(facing)
        near = np.bincount(i, minlength=n)
        dark = np.bincount(i, self.dark[j].astype(float), n)
        ask = (near == 0) | ((dark > 0) & (dark < near))
        lit[facing[(near > 0) & (dark == near)]] = 0.0
        if ask.any():
            lit[facing[ask]] = light(self.sight, P[facing[ask]], N[facing[ask]], self.L, self.reach)
        return lit


NEAR = 1.5              # node spacings: the nodes about a point that tell whether it is in a cast shadow


def check(lower, upper, contrast):
    """ValueError naming a setting of the tone curve that is out of range."""
    for name, v in (("shade_lower", lower), ("shade_upper", upper), ("contrast", contrast)):
        if isinstance(v, bool) or not isinstance(v, (int, float, np.floating)) or not np.isfinite(v) \
                or not 0.0 <= v <= 1.0:
            raise ValueError(f"{name} must be a number from 0 to 1, got {v!r}")
    if not lower < upper:
        raise ValueError(f"shade_lower ({lower:g}) must be below shade_upper ({upper:g}): the tone ramps "
                         "from the full shade up to the highlight threshold")


def tone(light, lower, upper, contrast=1.0):
    """The share of the paper the ink should cover at points of this ``light`` (Lambert's
    with cast shadows, 0..1): see the module's docstring."""
    light = np.asarray(light, float)
    ramp = np.clip((upper - light) / (upper - lower), 0.0, 1.0)
    c = float(contrast)
    return np.where(light < upper, DARKEST * ((1.0 - c) * FLAT + c * ramp), 0.0)


SHARES = ("all", "first", "rest")


def coverage(t, share):
    """The share of the paper one layer of marks should cover at tone ``t``: all of it,
    or of two layers drawn over each other the ``first`` all of it up to ONE_LAYER and
    the ``rest`` what is left, so that the two together cover t
    (1 - (1 - first)(1 - rest) = t)."""
    t = np.asarray(t, float)
    if share == "all":
        return t
    if share == "first":
        return np.minimum(t, ONE_LAYER)
    return np.where(t > ONE_LAYER, 1.0 - (1.0 - t) / (1.0 - ONE_LAYER), 0.0)


def darkness(t):
    """A tone as a share of the darkest (0..1)."""
    return np.clip(np.asarray(t, float) / DARKEST, 0.0, 1.0)
