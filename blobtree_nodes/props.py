"""Blender properties for the keys of the blobtree-1 format (one table: format.SPEC).

Hard limits are left wide on purpose: a zero radius or a NaN typed by an artist must
reach the compiler, which names it on the node, instead of being silently clamped.
"""
import math

import bpy

from ..model.format import SPEC
from .base import on_edit

# digits the node editor shows: a plain number shows PRECISION decimals; a length or an
# angle (shown in the scene's units) UNIT_PRECISION digits less those before the point,
# so two decimals up to 99.99 (1.1 reads "1.1 m", 12.34 "12.34 m")
PRECISION = 2
UNIT_PRECISION = 4

LABELS = {
    "center": "Center", "a": "Start", "b": "End", "radius": "Influence Radius", "strength": "Strength",
    "normal": "Normal", "circle_radius": "Circle Radius", "disc_radius": "Disc Radius",
    "half_size": "Half Size", "n": "Exponent", "translate": "Translate", "rotate": "Rotate",
    "scale": "Scale", "rate": "Rate",
}
# a key whose meaning depends on the node type gets that type's own label
KIND_LABELS = {("twist", "rate"): "Twist Rate", ("taper", "rate"): "Taper Rate", ("bend", "rate"): "Curvature"}
DEFAULTS = {
    "center": (0.0, 0.0, 0.0), "a": (0.0, 0.0, 0.0), "b": (0.0, 0.0, 1.0), "radius": 1.0, "strength": 1.0,
    "normal": (0.0, 0.0, 1.0), "circle_radius": 1.0, "disc_radius": 1.0, "half_size": (0.5, 0.5, 0.5),
    "n": 2.0, "translate": (0.0, 0.0, 0.0), "rotate": (0.0, 0.0, 0.0), "scale": (1.0, 1.0, 1.0), "rate": 0.0,
}
DESCRIPTIONS = {
    "center": "Where the primitive sits: its skeleton is centred here",
    "a": "One end of the segment",
    "b": "The other end of the segment",
    "radius": "Radius of influence: the field falls from its strength on the skeleton to 0 at this "
              "distance (the surface of a lone primitive lies at about 0.45 of it)",
    "strength": "Field value on the skeleton (a negative strength dents a blend)",
    "normal": "The axis across the primitive's plane; only its direction counts",
    "circle_radius": "Radius of the circle the field runs around (the field is a torus)",
    "disc_radius": "Radius of the flat disc the field surrounds",
    "half_size": "Half the box's extent along X, Y and Z; a 0 flattens the box",
    "n": "How sharply the inputs meet: 1 blends them, larger values approach their union",
    "translate": "Move the input field by this offset",
    "rotate": "Rotate the input field by these XYZ Euler angles (X first), after scaling",
    "scale": "Scale the input field along X, Y and Z (negative mirrors; 0 is not allowed)",
    "rate": "How strongly the input field is warped",
}
KIND_DESCRIPTIONS = {
    ("twist", "rate"): "Radians the input field turns about its Z axis per unit of height",
    ("taper", "rate"): "Change of the input field's X and Y scale per unit of height",
    ("bend", "rate"): "1 / bend radius: a positive value curls the input's X axis towards +Z; 0 leaves it straight",
}


def label(kind_name, key):
    """The name an artist reads for a key of a node type (on the node and in errors)."""
    return KIND_LABELS.get((kind_name, key), LABELS.get(key, key))


def description(kind_name, key):
    return KIND_DESCRIPTIONS.get((kind_name, key), DESCRIPTIONS[key])


def prop_for(key, kind, kind_name):
    d = DEFAULTS[key]
    common = dict(name=label(kind_name, key), description=description(kind_name, key), update=on_edit,
                  default=d)
    plain = dict(common, precision=PRECISION)
    units = dict(common, precision=UNIT_PRECISION)
    if kind in ("vec",):
        return bpy.props.FloatVectorProperty(size=3, subtype="TRANSLATION", unit="LENGTH", **units)
    if kind == "dir":
        return bpy.props.FloatVectorProperty(size=3, subtype="XYZ", **plain)
    if kind == "nonneg_vec":
        return bpy.props.FloatVectorProperty(size=3, subtype="XYZ_LENGTH", unit="LENGTH", soft_min=0.0, **units)
    if kind == "angles":
        return bpy.props.FloatVectorProperty(size=3, subtype="EULER", unit="ROTATION", **units)
    if kind == "scale":
        return bpy.props.FloatVectorProperty(size=3, subtype="XYZ", **plain)
    if kind == "pos":
        return bpy.props.FloatProperty(soft_min=0.001, soft_max=10.0, unit="LENGTH", **units)
    if kind == "ricci_n":
        return bpy.props.FloatProperty(soft_min=1.0, soft_max=16.0, **plain)
    return bpy.props.FloatProperty(soft_min=-10.0, soft_max=10.0, **plain)


def value_keys(kind_name):
    """The format's value keys (not children) of a node type, in table order."""
    return [k for k, (kind, _req) in SPEC[kind_name].items() if kind not in ("children", "children2", "child")]


def annotations(kind_name):
    return {k: prop_for(k, SPEC[kind_name][k][0], kind_name) for k in value_keys(kind_name)}


def is_vector(kind_name, key):
    return SPEC[kind_name][key][0] in ("vec", "dir", "nonneg_vec", "angles", "scale")


def finite(v):
    return all(math.isfinite(x) for x in v) if isinstance(v, list) else math.isfinite(v)
