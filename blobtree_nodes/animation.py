"""Animated node values. Blender evaluates the animation of the data in a depsgraph, and
a custom node tree is in none: its keyframes and drivers would never take effect. So a
tree's F-curves and drivers are evaluated here, at the scene's frame, and written into
the node properties (as Blender writes the animation it evaluates into the original
data): on every frame change, in the UI, in a bake and in a render (the handlers of
blobtree_nodes.follow). Drivers take their variables' values through the depsgraph
they are given (objects with their animation, parents and constraints); a scripted
expression may use its variables, ``frame`` and the functions of ``math``."""
import math

import bpy
from bpy_extras import anim_utils

# what a scripted driver's expression may use besides its variables and frame
_MATH = {k: getattr(math, k) for k in dir(math) if not k.startswith("_")}
_MATH.update(min=min, max=max, abs=abs, round=round, pow=pow, int=int, float=float, bool=bool)


class DriverError(ValueError):
    """A driver this extension cannot evaluate; the message names it."""


def channels(tree):
    """The tree's keyframed F-curves (of its action's slot)."""
    ad = tree.animation_data
    if ad is None or ad.action is None:
        return []
    bag = anim_utils.action_get_channelbag_for_slot(ad.action, ad.action_slot)
    return list(bag.fcurves) if bag is not None else []


def drivers(tree):
    ad = tree.animation_data
    return list(ad.drivers) if ad is not None else []


def depends_on_time(tree):
    """Whether the tree has animated or driven values."""
    return bool(channels(tree) or drivers(tree))


def _evaluated(obj, depsgraph):
    return obj.evaluated_get(depsgraph) if depsgraph is not None and isinstance(obj, bpy.types.Object) else obj


def _transform(var_target, depsgraph):
    obj = _evaluated(var_target.id, depsgraph)
    space = var_target.transform_space
    m = obj.matrix_world if space == "WORLD_SPACE" else (obj.matrix_basis if space == "TRANSFORM_SPACE"
                                                         else obj.matrix_local)
    loc, rot, scale = m.decompose()
    kind, _, axis = var_target.transform_type.partition("_")
    if kind == "LOC":
        return loc["XYZ".index(axis)]
    if kind == "SCALE":
        return sum(scale) / 3 if axis == "AVG" else scale["XYZ".index(axis)]
    if kind == "ROT":
        if axis == "W":
            return rot.w
        return rot.to_euler(var_target.rotation_mode if var_target.rotation_mode in
                            ("XYZ", "XZY", "YXZ", "YZX", "ZXY", "ZYX") else "XYZ")["XYZ".index(axis)]
    raise DriverError(f"a transform channel {var_target.transform_type} is not supported")


def _variable(var, depsgraph, where):
    t = var.targets
    if var.type == "SINGLE_PROP":
        if t[0].id is None:
            raise DriverError(f"{where}: variable '{var.name}' has no target")
        return float(_evaluated(t[0].id, depsgraph).path_resolve(t[0].data_path))
    if var.type == "TRANSFORMS":
        if t[0].id is None:
            raise DriverError(f"{where}: variable '{var.name}' has no object")
        return float(_transform(t[0], depsgraph))
    if var.type in ("LOC_DIFF", "ROTATION_DIFF"):
        if t[0].id is None or t[1].id is None:
            raise DriverError(f"{where}: variable '{var.name}' needs two objects")
        a, b = (_evaluated(x.id, depsgraph).matrix_world for x in t[:2])
        if var.type == "LOC_DIFF":
            return float((a.translation - b.translation).length)
        return float(a.to_quaternion().rotation_difference(b.to_quaternion()).angle)
    raise DriverError(f"{where}: variables of type {var.type} are not supported")


def driver_value(fc, frame, depsgraph):
    """The value a driver F-curve gives its property."""
    d = fc.driver
    where = f"the driver of {fc.data_path}[{fc.array_index}]"
    values = {v.name: _variable(v, depsgraph, where) for v in d.variables}
    if d.type == "SCRIPTED":
        try:
            x = float(eval(d.expression, {"__builtins__": {}, **_MATH}, {"frame": frame, **values}))
        except (NameError, SyntaxError, TypeError, ZeroDivisionError, ValueError) as e:
            raise DriverError(f"{where}: cannot evaluate '{d.expression}' ({e}); it may use its variables, "
                              "frame and math") from None
    elif not values:
        x = 0.0
    else:
        x = {"AVERAGE": lambda v: sum(v) / len(v), "SUM": sum, "MIN": min, "MAX": max}[d.type](list(values.values()))
    if len(fc.keyframe_points) or len(fc.modifiers):
        return fc.evaluate(x)
    return x


def _set(tree, fc, value):
    """Write a value into the property an F-curve drives; True if it changed."""
    head, _, attr = fc.data_path.rpartition(".")
    owner = tree.path_resolve(head) if head else tree
    cur = getattr(owner, attr)
    if hasattr(cur, "__len__"):
        if cur[fc.array_index] == value:
            return False
        cur[fc.array_index] = value
        return True
    if type(cur)(value) == cur:
        return False
    setattr(owner, attr, type(cur)(value))
    return True


def apply(tree, frame, depsgraph=None):
    """Write the tree's animated and driven values at ``frame``; True if any changed.
    DriverError names a driver that cannot be evaluated."""
    changed = False
    for fc in channels(tree):
        if not fc.mute:
            changed |= _set(tree, fc, fc.evaluate(frame))
    for fc in drivers(tree):
        if not fc.mute and fc.driver.is_valid:
            changed |= _set(tree, fc, driver_value(fc, frame, depsgraph))
    return changed

