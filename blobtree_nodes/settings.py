"""Illustration settings kept on the BlobTree node tree (saved with it), and their
mapping to the pure drawing style (strokes.style.Style) and its presets."""
import bpy

from ..agents.session import Settings as _RunSettings
from ..strokes import smarticles as sm
from ..strokes import style as ST

# Style settings mirrored as properties (the rest of Style keeps its defaults).
STYLE_PROPS = ("hatching", "stipples", "chains", "short", "hatch_field", "hatch_axis", "cross_hatching", "cross_field",
               "surface", "flock_size", "shade_lower", "shade_upper", "chain_step", "chain_angle",
               "stipple_every", "line_width", "contrast")
RUN_DEFAULTS = dict(grid_resolution=_RunSettings.resolution, agents=_RunSettings.agents, lod=_RunSettings.lod)


def _preset_values(style):
    v = {k: getattr(style, k) for k in STYLE_PROPS}
    v["hatch_field"] = v["hatch_field"].upper()
    v["cross_field"] = v["cross_field"].upper()
    v["surface"] = v["surface"].upper()
    if isinstance(style.weights, str):
        v["weights"] = style.weights.upper()
    else:
        v["weights"] = "CUSTOM"
        v.update({f"w_{k}": style.weights.get(k, 0.0) for k in ST.WEIGHT_NAMES})
    return dict(RUN_DEFAULTS, **v)


# the looks of the papers' figures, by operator-friendly identifier
PRESETS = {name.upper().replace("-", "_"): _preset_values(st) for name, st in ST.STYLES.items()}


def style_of(ink):
    """The pure Style of a tree's settings (raises ValueError naming a bad value)."""
    ch = {k: getattr(ink, k) for k in STYLE_PROPS}
    ch["hatch_field"] = ink.hatch_field.lower()
    ch["cross_field"] = ink.cross_field.lower()
    ch["surface"] = ink.surface.lower()
    ch["hatch_axis"] = tuple(ink.hatch_axis)
    if ink.weights == "CUSTOM":
        ch["weights"] = {k: getattr(ink, f"w_{k}") for k in ST.WEIGHT_NAMES}
    else:
        ch["weights"] = ink.weights.lower()
    return ST.style("outlines", **ch)


FIELD_ITEMS = [("DIR1", "First Principal", "Along the first principal direction"),
               ("DIR2", "Second Principal", "Along the second principal direction"),
               ("CONTOUR", "Contour", "Across the view direction, like contour lines"),
               ("AXIS", "Axis", "Along the axis, projected on the surface"),
               ("STRAIGHT", "Straight", "Keep the initial heading")]


def _weight(name, default):
    return bpy.props.FloatProperty(name=name.title(), default=default, min=0.0, max=100.0, soft_max=5.0,
                                   description=f"Weight of the {name} behaviour (Custom weights)")


class BlobTreeInkSettings(bpy.types.PropertyGroup):
    grid_resolution: bpy.props.IntProperty(name="Grid", default=20, min=8, max=128,
                                           description="About Grid^3 cubic blackboard cells over the model")
    agents: bpy.props.IntProperty(name="Agents", default=RUN_DEFAULTS["agents"], min=1, max=10000,
                                  description="Agents stepped together each system iteration")
    lod: bpy.props.FloatProperty(name="Level of Detail", default=0.5, min=0.0, max=1.0)
    seed: bpy.props.IntProperty(name="Seed", default=0, min=0)
    use_camera: bpy.props.BoolProperty(name="From Camera", default=True,
                                       description="Illustrate for the scene camera (else the viewport's view)")
    region_radius: bpy.props.FloatProperty(name="Region Radius", default=0.5, min=0.001, unit="LENGTH",
                                           description="Radius of the sphere around the 3D cursor that "
                                           "region requests use when no object is selected")
    # --- style (strokes.style.Style) ---
    hatching: bpy.props.BoolProperty(name="Hatching", default=False, description="Hatch the shaded regions")
    stipples: bpy.props.BoolProperty(name="Stipples", default=False, description="Stipples from wandering agents")
    chains: bpy.props.BoolProperty(name="Chain Strokes", default=False,
                                   description="Strokes started from the silhouette and crease chains")
    short: bpy.props.BoolProperty(name="Short Strokes", default=False,
                                  description="Short strokes centred on the polygon centres")
    hatch_field: bpy.props.EnumProperty(name="Flow Field", default="DIR1", items=FIELD_ITEMS,
                                        description="The direction hatching and short strokes follow")
    cross_field: bpy.props.EnumProperty(name="Cross Field", default="DIR2", items=FIELD_ITEMS,
                                        description="The direction of the cross-hatching")
    hatch_axis: bpy.props.FloatVectorProperty(name="Axis", default=(0.0, 0.0, 1.0), size=3, subtype="DIRECTION")
    cross_hatching: bpy.props.BoolProperty(name="Cross-Hatching", default=True,
                                           description="A second hatching layer in the darkest shade")
    surface: bpy.props.EnumProperty(name="Regions", default="ALL",
                                    items=[("ALL", "All", "Hatch anywhere in shade"),
                                           ("CONVEX", "Convex", "Only convex regions"),
                                           ("CONCAVE", "Concave", "Only concave regions")])
    weights: bpy.props.EnumProperty(
        name="Weights", default="HATCHING",
        items=[(k.upper(), k.title(), f"The {k} steering weights") for k in sm.PRESETS] +
              [("CUSTOM", "Custom", "The weights below")])
    w_flow: _weight("flow", 1.0)
    w_wander: _weight("wander", 0.0)
    w_separation: _weight("separation", 0.0)
    w_alignment: _weight("alignment", 0.0)
    w_cohesion: _weight("cohesion", 0.0)
    w_containment: _weight("containment", 0.0)
    flock_size: bpy.props.IntProperty(name="Flock Size", default=1, min=1, max=64,
                                      description="Smarticles per flock (1: single smarticles)")
    shade_lower: bpy.props.FloatProperty(name="Shade Lower", default=0.25, min=0.0, max=1.0,
                                         description="Below this light every start gets a stroke")
    shade_upper: bpy.props.FloatProperty(name="Shade Upper", default=0.6, min=0.0, max=1.0,
                                         description="Above this light no stroke (between: the penumbra)")
    chain_step: bpy.props.IntProperty(name="Chain Step", default=3, min=1, max=10000,
                                      description="Every n-th chain point starts a stroke")
    chain_angle: bpy.props.FloatProperty(name="Chain Angle", default=90.0, min=-180.0, max=180.0,
                                         description="Degrees between the chain and its strokes")
    stipple_every: bpy.props.IntProperty(name="Stipple Every", default=3, min=1, max=1000,
                                         description="A stipple at every k-th wander step")
    line_width: bpy.props.FloatProperty(name="Line Width", default=1.0, min=0.01, max=100.0)
    contrast: bpy.props.FloatProperty(name="Light Contrast", default=1.0, min=0.0, max=1.0,
                                      description="How much the light sets stroke width and opacity")


classes = (BlobTreeInkSettings,)
