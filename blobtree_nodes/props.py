"""Blender properties for the keys of the blobtree-1 format (one table: format.SPEC).

Hard limits are left wide on purpose: a zero radius or a NaN typed by an artist must
reach the compiler, which names it on the node, instead of being silently clamped.
"""
import math

import bpy

from ..model.format import SPEC
from .base import on_edit

LABELS = {
    "center": "Center", "a": "Start", "b": "End", "radius": "Radius", "strength": "Strength",
    "normal": "Normal", "circle_radius": "Circle Radius", "disc_radius": "Disc Radius",
    "half_size": "Half Size", "n": "Exponent", "translate": "Translate", "rotate": "Rotate",
    "scale": "Scale", "rate": "Rate",
}
DEFAULTS = {
    "center": (0.0, 0.0, 0.0), "a": (0.0, 0.0, 0.0), "b": (0.0, 0.0, 1.0), "radius": 1.0, "strength": 1.0,
    "normal": (0.0, 0.0, 1.0), "circle_radius": 1.0, "disc_radius": 1.0, "half_size": (0.5, 0.5, 0.5),
    "n": 2.0, "translate": (0.0, 0.0, 0.0), "rotate": (0.0, 0.0, 0.0), "scale": (1.0, 1.0, 1.0), "rate": 0.0,
}
DESCRIPTIONS = {
    "radius": "Radius of influence: the field falls from the skeleton to 0 at this distance",
    "strength": "Field value on the skeleton",
    "rate": "Warp rate (twist: radians per unit along z; taper: scale change per unit; bend: 1 / radius)",
    "n": "Ricci blend exponent (1 = blend, large = union)",
}


def prop_for(key, kind):
    name = LABELS.get(key, key)
    desc = DESCRIPTIONS.get(key, "")
    d = DEFAULTS[key]
    common = dict(name=name, description=desc, update=on_edit)
    if kind in ("vec",):
        return bpy.props.FloatVectorProperty(size=3, subtype="TRANSLATION", unit="LENGTH", default=d, **common)
    if kind == "dir":
        return bpy.props.FloatVectorProperty(size=3, subtype="XYZ", default=d, **common)
    if kind == "nonneg_vec":
        return bpy.props.FloatVectorProperty(size=3, subtype="XYZ_LENGTH", unit="LENGTH", soft_min=0.0,
                                             default=d, **common)
    if kind == "angles":
        return bpy.props.FloatVectorProperty(size=3, subtype="EULER", unit="ROTATION", default=d, **common)
    if kind == "scale":
        return bpy.props.FloatVectorProperty(size=3, subtype="XYZ", default=d, **common)
    if kind == "pos":
        return bpy.props.FloatProperty(soft_min=0.001, soft_max=10.0, unit="LENGTH", default=d, **common)
    if kind == "ricci_n":
        return bpy.props.FloatProperty(soft_min=1.0, soft_max=16.0, default=d, **common)
    return bpy.props.FloatProperty(default=d, soft_min=-10.0, soft_max=10.0, **common)


def value_keys(kind_name):
    """The format's value keys (not children) of a node type, in table order."""
    return [k for k, (kind, _req) in SPEC[kind_name].items() if kind not in ("children", "children2", "child")]


def annotations(kind_name):
    return {k: prop_for(k, SPEC[kind_name][k][0]) for k in value_keys(kind_name)}


def is_vector(kind_name, key):
    return SPEC[kind_name][key][0] in ("vec", "dir", "nonneg_vec", "angles", "scale")


def finite(v):
    return all(math.isfinite(x) for x in v) if isinstance(v, list) else math.isfinite(v)
