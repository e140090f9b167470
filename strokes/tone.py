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

DARKEST = 0.5           # the share of the paper the ink covers at the darkest tone
FLAT = 0.5              # contrast 0: the tone of every point in shade, as a share of DARKEST
ONE_LAYER = 0.28        # hatching: the tone one layer of lines reaches; darker tones cross it with a second


def lambert(normals, light_dir):
    """max(0, n . L) per point (``light_dir`` towards the light, any length)."""
    L = np.asarray(light_dir, float)
    L = L / np.linalg.norm(L)
    return np.maximum(0.0, np.asarray(normals, float).reshape(-1, 3) @ L)


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


def darkness(t):
    """A tone as a share of the darkest (0..1)."""
    return np.clip(np.asarray(t, float) / DARKEST, 0.0, 1.0)
