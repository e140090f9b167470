"""Illustration settings kept on the BlobTree node tree (saved with it), and their
mapping to the pure drawing style (strokes.style.Style) and its presets."""
import bpy

from ..agents.session import Settings as _RunSettings
from ..strokes import smarticles as sm
from ..strokes import style as ST

_STYLE = ST.Style()              # the style's defaults are the properties' defaults

# Style settings mirrored as properties (the rest of Style keeps its defaults). A preset
# sets these and nothing else: never the grid, agents, level of detail or seed.
STYLE_PROPS = ("hatching", "stipples", "chains", "short", "hatch_field", "hatch_axis", "cross_hatching", "cross_field",
               "surface", "flock_size", "shade_lower", "shade_upper", "chain_step", "chain_angle",
               "stipple_every", "line_width", "contrast")
PRESET_PROPS = STYLE_PROPS + ("weights",) + tuple(f"w_{k}" for k in ST.WEIGHT_NAMES)


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
    return v


# the looks of the papers' figures, by operator-friendly identifier
PRESETS = {name.upper().replace("-", "_"): _preset_values(st) for name, st in ST.STYLES.items()}
PRESET_TIPS = {
    "OUTLINES": "Feature outlines only: silhouettes and creases, hidden lines removed",
    "STIPPLED": "Outlines and stipples in the shade (MASSRIS figures 1 and 6)",
    "HATCHED": "Outlines and hatching along the first principal direction, cross-hatched in the darkest shade",
    "FLOCKED": "Outlines and sketchy hatching by flocks of four smarticles (Smarticles figure 4)",
    "SILHOUETTE_SHADING": "Outlines and strokes started from the feature chains (Smarticles figure 3, left)",
    "SHORT_STROKES": "Outlines, short strokes on the polygon centres and stipples (MASSRIS figure 1)",
    "TECHNICAL": "Outlines and horizontal hatching along the level lines of the vertical axis "
                 "(Smarticles figure 3, right)",
    "CONTOUR": "Outlines and hatching across the view direction, like contour lines",
}


def apply_preset(ink, key):
    """Set a tree's style settings to a preset's (and only those)."""
    for name, value in PRESETS[key].items():
        setattr(ink, name, value)


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


FIELD_ITEMS = [(key, name, tip, "NONE", number) for key, name, tip, number in (   # numbered as saved files have them
    ("DIR1", "First Principal", "Along the first principal direction of curvature", 0),
    ("DIR2", "Second Principal", "Along the second principal direction of curvature", 1),
    ("DIAGONAL", "Diagonal", "Half way between the principal directions of curvature, 45 degrees from each", 6),
    ("CONTOUR", "Contour", "Across the view direction, like contour lines", 2),
    ("AXIS", "Axis", "Along the axis, projected on the surface", 3),
    ("LEVEL", "Level Lines", "Along the level lines of the axis (horizontal for the vertical axis)", 4),
    ("STRAIGHT", "Straight", "Keep the initial heading", 5))]
WEIGHT_TIPS = {
    "flow": "Follow the flow field",
    "wander": "Small random changes of heading (sketchy strokes, stipples)",
    "separation": "Keep away from flockmates (parallel strokes)",
    "alignment": "Head where the flockmates head",
    "cohesion": "Stay with the flock",
    "containment": "Turn back before leaving the region",
}


def _weight(name, default):
    return bpy.props.FloatProperty(name=name.title(), default=default, min=0.0, max=100.0, soft_max=5.0,
                                   description=f"Custom weight of a behaviour: {WEIGHT_TIPS[name]}")


def put_on_paper(tree, context):
    """The scene on white paper (what it replaced kept on the tree, to give back), the
    screen's 3D viewports on the world's white, the preview mesh white."""
    from ..grease_pencil import scene as S
    from . import preview
    was = S.paper(context.scene)
    if was:
        tree.ink.paper_restore = was
    S.paper_viewports(context.screen, True)
    preview.paper_look(tree)


def _paper(self, context):
    from ..grease_pencil import scene as S
    if context.scene is None:
        return
    if self.paper:
        put_on_paper(self.id_data, context)
    else:
        from . import preview
        S.unpaper(context.scene, self.paper_restore)
        S.paper_viewports(context.screen, False)
        preview.paper_look(self.id_data)
        self.paper_restore = ""


def _render_preview(self, context):
    from ..grease_pencil import scene as S
    tree = self.id_data
    obj = getattr(tree, "preview_object", None)
    if obj is not None:
        obj.hide_render = not self.render_preview
    if self.paper and context.scene is not None:
        S.depth_pass(context.scene, not self.render_preview)


def _scene_range(self, context):
    """Scene Range switched off: a tree whose own range was never set starts it as the
    range in effect (the scene's, which the fields showed), not from the defaults; one
    that was set (by the artist or a script) keeps it."""
    never_set = not (self.is_property_set("frame_start") or self.is_property_set("frame_end"))
    if not self.use_scene_range and never_set and context.scene is not None:
        self.frame_start, self.frame_end = context.scene.frame_start, context.scene.frame_end


def _start_moved(self, context):
    if self.frame_end < self.frame_start:          # as the timeline's Start pushes its End
        self.frame_end = self.frame_start


def _end_moved(self, context):
    if self.frame_start > self.frame_end:
        self.frame_start = self.frame_end


def bake_range(ink, scene):
    """The frames a bake of the tree illustrates: the scene's range or the tree's own."""
    if ink.use_scene_range:
        return scene.frame_start, scene.frame_end
    return ink.frame_start, ink.frame_end


class BlobTreeInkSettings(bpy.types.PropertyGroup):
    grid_resolution: bpy.props.IntProperty(
        name="Grid", default=_RunSettings.resolution, min=8, max=128,
        description="Resolution of the agents' blackboard: about Grid^3 cubic cells over the model (finer finds "
                    "smaller features and takes longer; the strokes' density stays)")
    agents: bpy.props.IntProperty(
        name="Agents", default=_RunSettings.agents, min=1, max=10000,
        description="Agents stepped together each system iteration (more agents: fewer, larger iterations)")
    lod: bpy.props.FloatProperty(
        name="Level of Detail", default=_RunSettings.lod, min=0.0, max=1.0,
        description="How much the agents favour flat, quiet parts of the surface against its busy parts "
                    "(MASSRIS's user level of detail, 0 to 1)")
    seed: bpy.props.IntProperty(
        name="Seed", default=_RunSettings.seed, min=0,
        description="Seed of the random choices (exploring agents, which strokes go in the penumbra, wander): "
                    "the same seed draws the same strokes, in every frame; another seed, another set")
    line_silhouette: bpy.props.BoolProperty(
        name="Silhouette", default="silhouette" in _RunSettings.kinds,
        description="Trace Feature Outlines and Find Features trace silhouettes: where the surface turns away "
                    "from the eye (layer Silhouette)")
    line_crease: bpy.props.BoolProperty(
        name="Crease", default="crease" in _RunSettings.kinds,
        description="Trace Feature Outlines and Find Features trace creases: where the surface folds, the edges "
                    "of unions, intersections and differences (layer Crease)")
    line_curvature: bpy.props.BoolProperty(
        name="Curvature", default="curvature" in _RunSettings.kinds,
        description="Trace Feature Outlines and Find Features trace curvature-sign lines: where the surface "
                    "turns from convex to concave (layer Curvature; none across flat parts)")
    line_suggestive: bpy.props.BoolProperty(
        name="Suggestive", default="suggestive" in _RunSettings.kinds,
        description="Trace Feature Outlines and Find Features trace suggestive contours: where the surface "
                    "comes closest to turning away from the eye without doing so, a contour from a nearby "
                    "viewpoint (zeros of the radial curvature, DeCarlo et al. 2003; layer Suggestive)")
    line_ridges: bpy.props.BoolProperty(
        name="Ridges", default="ridges" in _RunSettings.kinds,
        description="Trace Feature Outlines and Find Features trace apparent ridges: the crests where the "
                    "surface, as seen, bends most sharply (peaks of the view-dependent curvature, Judd et al. "
                    "2007; layer Ridges)")
    use_camera: bpy.props.BoolProperty(
        name="From Camera", default=True,
        description="Illustrate the model as the scene camera sees it (else as the 3D viewport does)")
    region: bpy.props.EnumProperty(
        name="Region", default="AUTO",
        description="Where Place Strokes and Find Features work",
        items=[("AUTO", "Selection or Whole Model",
                "The bounds of the selected objects; the whole model when nothing usable is selected"),
               ("CURSOR", "Around the 3D Cursor",
                "A sphere around the 3D cursor, its radius the Region Size times the model's size")])
    region_size: bpy.props.FloatProperty(
        name="Region Size", default=0.25, min=0.01, max=2.0, subtype="FACTOR",
        description="Radius of the sphere around the 3D cursor, as a fraction of the model's size")
    paper: bpy.props.BoolProperty(
        name="Paper", default=True, update=_paper,
        description="Ink on white paper: a white world in renders, Material Preview and the Solid viewport's "
                    "background, a view transform that keeps white white, the preview mesh in white (off: the "
                    "scene's own look is left as it is)")
    paper_restore: bpy.props.StringProperty(options={"HIDDEN"},
                                            description="What Paper replaced in the scene (restored when it is off)")
    render_frames: bpy.props.BoolProperty(
        name="Illustrate Rendered Frames", default=True,
        description="When a render reaches a frame the ink shows no drawing made for (a drawing made from this "
                    "model, light, style and camera is kept, as are a bake's and the artist's), illustrate it "
                    "first: the outlines and the style's strokes")
    use_scene_range: bpy.props.BoolProperty(
        name="Scene Range", default=True, update=_scene_range,
        description="Bake the scene's frame range (the timeline's Start and End); off: the range below")
    frame_start: bpy.props.IntProperty(name="Start", default=1, min=0, update=_start_moved,
                                       description="First frame a bake illustrates (when not the scene's range)")
    frame_end: bpy.props.IntProperty(name="End", default=24, min=0, update=_end_moved,
                                     description="Last frame a bake illustrates (when not the scene's range)")
    render_preview: bpy.props.BoolProperty(
        name="Render Preview Mesh", default=False, update=_render_preview,
        description="Render the preview mesh too (off: only the ink shows in renders)")
    # --- style (strokes.style.Style) ---
    hatching: bpy.props.BoolProperty(name="Hatching", default=_STYLE.hatching,
                                     description="Place Strokes draws hatching in the shaded regions")
    stipples: bpy.props.BoolProperty(name="Stipples", default=_STYLE.stipples,
                                     description="Place Strokes draws stipples from wandering smarticles in the shade")
    chains: bpy.props.BoolProperty(name="Chain Strokes", default=_STYLE.chains,
                                   description="Place Strokes draws strokes started from the silhouette and crease "
                                               "chains (traces the outlines first)")
    short: bpy.props.BoolProperty(name="Short Strokes", default=_STYLE.short,
                                  description="Place Strokes draws short strokes through points spread over the shade")
    hatch_field: bpy.props.EnumProperty(name="Flow Field", default=_STYLE.hatch_field.upper(), items=FIELD_ITEMS,
                                        description="The direction hatching and short strokes follow")
    cross_field: bpy.props.EnumProperty(name="Cross Field", default=_STYLE.cross_field.upper(), items=FIELD_ITEMS,
                                        description="The direction of the cross-hatching")
    hatch_axis: bpy.props.FloatVectorProperty(name="Axis", default=_STYLE.hatch_axis, size=3, subtype="DIRECTION",
                                              description="The axis of the Axis and Level Lines flow fields")
    cross_hatching: bpy.props.BoolProperty(name="Cross-Hatching", default=_STYLE.cross_hatching,
                                           description="A second hatching layer in the darkest shade")
    surface: bpy.props.EnumProperty(name="Hatch Where", default=_STYLE.surface.upper(),
                                    description="Where hatching starts (and, when limited, where it stops: at a "
                                                "change of the curvature's sign)",
                                    items=[("ALL", "All", "Hatch anywhere in shade"),
                                           ("CONVEX", "Convex", "Only convex regions"),
                                           ("CONCAVE", "Concave", "Only concave regions")])
    weights: bpy.props.EnumProperty(
        name="Steering", default=_STYLE.weights.upper(),
        description="How the smarticles steer: a preset of behaviour weights, or custom weights",
        items=[(k.upper(), k.title(), f"The {k} steering weights") for k in sm.PRESETS] +
              [("CUSTOM", "Custom", "The weights below")])
    w_flow: _weight("flow", sm.PRESETS["hatching"]["flow"])
    w_wander: _weight("wander", sm.PRESETS["hatching"]["wander"])
    w_separation: _weight("separation", sm.PRESETS["hatching"]["separation"])
    w_alignment: _weight("alignment", sm.PRESETS["hatching"]["alignment"])
    w_cohesion: _weight("cohesion", sm.PRESETS["hatching"]["cohesion"])
    w_containment: _weight("containment", sm.PRESETS["hatching"].get("containment", 0.0))
    flock_size: bpy.props.IntProperty(name="Flock Size", default=_STYLE.flock_size, min=1, max=64,
                                      description="Smarticles per flock, side by side (1: single smarticles)")
    shade_lower: bpy.props.FloatProperty(name="Shade Lower", default=_STYLE.shade_lower, min=0.0, max=1.0,
                                         description="Below this light the ink is at its darkest (form and cast shadows)")
    shade_upper: bpy.props.FloatProperty(name="Shade Upper", default=_STYLE.shade_upper, min=0.0, max=1.0,
                                         description="The highlight threshold: above this light the paper stays white")
    chain_step: bpy.props.IntProperty(name="Chain Step", default=_STYLE.chain_step, min=1, max=10000,
                                      description="Every n-th point of the feature chains starts a stroke")
    chain_angle: bpy.props.FloatProperty(name="Chain Angle", default=_STYLE.chain_angle, min=-180.0, max=180.0,
                                         description="Degrees between a feature chain and the strokes started from it")
    stipple_every: bpy.props.IntProperty(name="Stipple Every", default=_STYLE.stipple_every, min=1, max=1000,
                                         description="Stipples are chosen among every k-th step of a wandering "
                                                     "smarticle (and the points about it)")
    line_width: bpy.props.FloatProperty(name="Line Width", default=_STYLE.line_width, min=0.01, max=100.0,
                                        description="Width of every line and dot, times the base width (about a "
                                                    "pixel at 1024 pixels in a view framing the model)")
    contrast: bpy.props.FloatProperty(name="Light Contrast", default=_STYLE.contrast, min=0.0, max=1.0,
                                      description="How much of the tonal range the light spans (1: from the highlight to the "
                                                  "full shade; 0: one flat tone over all that is not highlight)")


classes = (BlobTreeInkSettings,)
