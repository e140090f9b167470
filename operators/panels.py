"""Sidebar panels of the 3D viewport and the node editor ("BlobTree Ink" tab): the
active tree expanded (its requests, preset looks, settings, style, ink layers and
animation: the bake range, Bake and Clear, the frames drawn), the other trees as one
row each, and the latest run's figures."""
import bpy
import numpy as np

from ..blackboard.board import FEATURE_KINDS
from ..blobtree_nodes import preview, wrap
from ..blobtree_nodes.base import SHOW_ERROR, draw_error, shown_name
from ..blobtree_nodes.compile import output_nodes
from ..blobtree_nodes.panels import nodes_with_errors
from ..blobtree_nodes.settings import PRESETS
from ..grease_pencil import views
from . import frames as FR
from . import jobs
from .common import TREE, active_tree, blobtrees, focus, ink_name
from .illustrate import REQUESTS, last_run
from .menus import REQUEST_ICONS


def shown_tree(context):
    """The tree the panels show: the active one (common.active_tree), else the one last
    worked on (common.focus: its preview may be off), else the first."""
    tree = active_tree(context)
    if tree is not None:
        return focus(tree)
    trees = blobtrees()
    return focus() or (trees[0] if trees else None)


SHOWN_ERRORS = 3            # nodes whose error the panel spells out; the others are named
NO_OUTPUT = "The tree has no Model Output: add one (Shift+A in the node editor, Output) and link the model to it"


def _draw_errors(layout, context, tree):
    """What keeps the tree from compiling, at the top where the artist looks: no Model
    Output, and the nodes with an error, each a button that makes it the active node
    (and brings it into view in the node editor), its error below it."""
    broken, output = nodes_with_errors(tree), bool(output_nodes(tree))
    if output and not broken:
        return
    width = wrap.region_text_width(context, context.region.width)
    if not output:                                 # (a new tree has no node: nothing says what it needs)
        col = layout.column(align=True)
        col.alert = True
        for i, line in enumerate(wrap.lines(NO_OUTPUT, width, context)):
            col.label(text=line, icon="ERROR" if i == 0 else "BLANK1")
    if not broken:
        return
    col = layout.column(align=True)
    col.alert = True
    many = len(broken) > 1
    head = f"{len(broken)} node{'s' if many else ''} with an error: nothing new is drawn until " \
        f"{'they are' if many else 'it is'} mended"
    for i, line in enumerate(wrap.lines(head, width, context)):
        col.label(text=line, icon="ERROR" if i == 0 else "BLANK1")
    for i, n in enumerate(broken):
        op = col.operator(SHOW_ERROR, text=shown_name(n), icon="NODE")
        op.tree_name, op.node_name, op.frame = tree.name, n.name, True
        if i < SHOWN_ERRORS:
            draw_error(col, context, n, width)


STALE = "The ink was drawn before the model changed: a Look draws it again"
STALE_HIDDEN = "The models in front of this one moved or changed since the ink was drawn: a Look draws it again"
STALE_VIEW = "The ink was drawn for another view than the camera's: a Look draws it again"


def _draw_stale(layout, context, tree):
    """Say so when the ink shown on this frame was drawn for another model than the
    one the preview shows (an edit, a moved object the tree follows, another frame of
    an animation), or, drawn from the camera, for a camera that saw the model otherwise
    (the camera or the model moved since; a viewport's ink is drawn for the view it was
    asked from, and the artist looks about), or when the other models that hide its
    lines have moved or changed since (one that stood between the eye and the model, or
    one that has come between)."""
    obj, key = bpy.data.objects.get(ink_name(tree)), preview.shown_model(tree)
    drawn = FR.DRAWN                                          # (the single strokes are the artist's own)
    if obj is None or obj.type != "GREASEPENCIL" or key is None:
        return
    frame, scene = context.scene.frame_current, context.scene
    if views.other_model(obj, drawn, frame, key):
        say = STALE
    elif tree.ink.use_camera and _other_camera(obj, drawn, frame, scene, tree):
        say = STALE_VIEW
    elif views.other_hiders(obj, drawn, frame, lambda eye: jobs.hiders_now(scene, tree, eye)):
        say = STALE_HIDDEN
    else:
        return
    col = layout.column(align=True)
    col.alert = True
    for i, line in enumerate(wrap.lines(say, wrap.region_text_width(context, context.region.width), context)):
        col.label(text=line, icon="INFO" if i == 0 else "BLANK1")


def _other_camera(obj, layers, frame, scene, tree):
    """Whether a drawing of ``layers`` shown on ``frame`` was drawn for an eye that sees the
    model (its preview's middle) otherwise than the scene camera does now."""
    eye, shown = jobs.camera_eye(scene), tree.preview_object
    if eye is None or shown is None:
        return False
    box = np.array([tuple(c) for c in shown.bound_box], float)
    inverse = jobs.placement(tree).inverted_safe()
    return bool(views.unfit(obj, layers, frame, np.array(jobs.to_model(inverse, eye)), box.mean(axis=0)))


def _draw_tree(layout, context, tree):
    """The requests and looks, then what keeps the tree from being drawn or the ink
    from fitting it (below them, so a message that comes or goes does not move the
    buttons under the artist's pointer), then the settings."""
    col = layout.column(align=True)
    for ident, label, _ in REQUESTS:
        op = col.operator("blobtree_ink.illustrate", text=label, icon=REQUEST_ICONS[ident])
        op.tree_name, op.request = tree.name, ident
    layout.label(text="Looks (set the style and draw it)")
    grid = layout.grid_flow(columns=2, align=True)
    for key in PRESETS:
        op = grid.operator("blobtree_ink.illustrate", text=key.replace("_", " ").title())
        op.tree_name, op.preset, op.request = tree.name, key, "PLACE_STROKES"
    _draw_errors(layout, context, tree)
    _draw_stale(layout, context, tree)
    s = tree.ink
    layout.label(text="Lines to trace")
    grid = layout.grid_flow(row_major=True, columns=2, even_columns=True, align=True)   # the lines, two a row
    for kind in FEATURE_KINDS:
        grid.prop(s, f"line_{kind}", toggle=True)
    col = layout.column(align=True)
    col.prop(s, "grid_resolution")
    col.prop(s, "agents")
    col.prop(s, "lod")
    col.prop(s, "seed")
    col = layout.column(align=True)
    row = col.row(align=True)
    row.prop(s, "use_camera")
    row.operator("blobtree_ink.frame_camera", icon="CAMERA_DATA").tree_name = tree.name
    col.prop(s, "region", text="")
    if s.region == "CURSOR":
        col.prop(s, "region_size")
    col = layout.column(align=True)
    row = col.row(align=True)
    row.prop(tree, "show_preview")                 # off: the mesh goes, and the ink is seen alone
    res = row.row(align=True)
    res.active = tree.show_preview
    res.prop(tree, "preview_resolution", text="")
    col.prop(s, "paper")
    col.prop(s, "render_preview")


def _draw_others(layout, shown):
    others = [t for t in blobtrees() if t != shown]
    if not others:
        return
    col = layout.column(align=True)
    col.label(text="Other BlobTrees")
    for t in others:
        col.operator("blobtree_ink.activate_tree", text=t.name, icon="META_BALL").tree_name = t.name


def _draw_style(layout, s):
    col = layout.column(align=True)
    row = col.row(align=True)
    row.prop(s, "hatching", toggle=True)
    row.prop(s, "stipples", toggle=True)
    row = col.row(align=True)
    row.prop(s, "chains", toggle=True)
    row.prop(s, "short", toggle=True)
    col = layout.column(align=True)
    _choice(col, s, "hatch_field")
    if {"AXIS", "LEVEL"} & {s.hatch_field, s.cross_field}:
        col.prop(s, "hatch_axis")
    col.prop(s, "cross_hatching")
    if s.cross_hatching:
        _choice(col, s, "cross_field")
    _choice(col, s, "surface")
    _choice(col, s, "weights")
    if s.weights == "CUSTOM":
        for name in ("w_flow", "w_wander", "w_separation", "w_alignment", "w_cohesion", "w_containment"):
            col.prop(s, name)
    col.prop(s, "flock_size")
    col = layout.column(align=True)
    col.prop(s, "shade_lower")
    col.prop(s, "shade_upper")
    col.prop(s, "chain_step")
    col.prop(s, "chain_angle")
    col.prop(s, "stipple_every")
    col.prop(s, "line_width")
    col.prop(s, "contrast")


def _choice(col, s, name):
    """A menu with its whole name beside it (the default label is cut short in a
    sidebar of the default width)."""
    row = col.split(factor=0.42, align=True)
    row.label(text=s.bl_rna.properties[name].name)
    row.prop(s, name, text="")


def _draw_layers(layout, tree):
    obj = bpy.data.objects.get(ink_name(tree))
    if obj is None or obj.type != "GREASEPENCIL":
        layout.label(text="Nothing drawn yet")
        return
    col = layout.column(align=True)
    frame = bpy.context.scene.frame_current
    for layer in obj.data.layers:
        n = FR.strokes_at(layer, frame)
        row = col.row(align=True)
        row.active = n > 0                  # an empty layer greyed out
        op = row.operator("blobtree_ink.toggle_layer", text=f"{layer.name} ({n})",
                          icon="HIDE_ON" if layer.hide else "HIDE_OFF", depress=n > 0 and not layer.hide)
        op.object_name, op.layer = obj.name, layer.name
        clear = row.row(align=True)
        clear.enabled = n > 0
        op = clear.operator("blobtree_ink.clear_layer", text="", icon="X")
        op.object_name, op.layer = obj.name, layer.name


def _draw_last_run(layout, context, tree):
    if last_run.get("tree") != tree.name:          # (the latest run was another tree's)
        return
    col = layout.column(align=True)
    state, pct = last_run.get("state", ""), 100 * last_run.get("fraction", 0.0)
    if state == "running":
        col.label(text=f"Running: {pct:.0f} % ({last_run.get('stage', '')})")
    elif state == "stopped":
        col.label(text=f"Last run: stopped at {pct:.0f} %")
    else:
        col.label(text=f"Last run: {state}")
    if state in ("done", "stopped") and changed_since(last_run):
        col.label(text="Undone or edited since", icon="INFO")
        return
    if state in ("undone", "cancelled"):           # what it had drawn went with it
        col.label(text="Nothing drawn")
        return
    frame = context.scene.frame_current
    drawn_on = (last_run.get("left") or {}).get("frame", frame)
    where = f" (drawn on frame {drawn_on})" if drawn_on != frame else ""
    col.label(text=f"Strokes: {last_run.get('strokes', 0)}{where}")
    if last_run.get("iterations"):
        col.label(text=f"Agents' iterations: {last_run['iterations']}")


def changed_since(run):
    """Whether the ink a run left (its object's strokes per layer on its frame) is no
    longer what it shows: Ctrl+Z took the run back, or the artist edited its strokes."""
    left = run.get("left")
    if left is None:
        return False
    obj = bpy.data.objects.get(left["object"])
    return obj is None or obj.type != "GREASEPENCIL" or FR.shown_counts(obj, left["frame"]) != left["counts"]


class _Sidebar:
    bl_region_type = "UI"
    bl_category = "BlobTree Ink"


class VIEW3D_PT_blobtree_ink(_Sidebar, bpy.types.Panel):
    bl_label = "BlobTree Ink"
    bl_space_type = "VIEW_3D"

    def draw(self, context):
        tree = shown_tree(context)
        if tree is None:
            self.layout.operator("blobtree_ink.import_json", icon="IMPORT")
            return
        self.layout.label(text=tree.name, icon="META_BALL")
        _draw_tree(self.layout, context, tree)
        _draw_others(self.layout, tree)
        _draw_last_run(self.layout, context, tree)


class NODE_PT_blobtree_ink(_Sidebar, bpy.types.Panel):
    bl_label = "BlobTree Ink"
    bl_space_type = "NODE_EDITOR"

    @classmethod
    def poll(cls, context):
        return getattr(context.space_data, "tree_type", "") == TREE and \
            context.space_data.node_tree is not None

    def draw(self, context):
        focus(context.space_data.node_tree)
        _draw_tree(self.layout, context, context.space_data.node_tree)
        _draw_last_run(self.layout, context, context.space_data.node_tree)


def _sub_panel(space, parent, ident, label, draw, closed=False):
    """A sub-panel of the sidebar's BlobTree Ink panel that shows while a tree is shown:
    ``draw(layout, tree, scene)``."""
    class Panel(_Sidebar, bpy.types.Panel):
        bl_label = label
        bl_space_type = space
        bl_parent_id = parent
        bl_options = {"DEFAULT_CLOSED"} if closed else set()

        @classmethod
        def poll(cls, context):
            return shown_tree(context) is not None

        def draw(self, context):
            draw(self.layout, shown_tree(context), context.scene)
    Panel.__name__ = f"{space}_PT_blobtree_ink_{ident}"
    Panel.bl_idname = Panel.__name__
    return Panel


def _draw_animation(layout, tree, scene):
    s = tree.ink
    col = layout.column(align=True)
    col.prop(s, "use_scene_range")
    row = col.row(align=True)
    if s.use_scene_range:
        row.enabled = False
        row.prop(scene, "frame_start", text="Start")
        row.prop(scene, "frame_end", text="End")
    else:
        row.prop(s, "frame_start")
        row.prop(s, "frame_end")
    row = layout.row(align=True)
    op = row.operator("blobtree_ink.bake", text="Bake", icon="RENDER_ANIMATION")
    op.tree_name = tree.name
    op = row.operator("blobtree_ink.clear_frames", text="Clear", icon="TRASH")
    op.tree_name = tree.name
    drawn = FR.drawn_frames(tree)
    layout.label(text=f"Drawn frames: {FR.spans(drawn)}" if drawn else "No frame drawn yet")
    layout.prop(s, "render_frames")


def _sub_panels(space, parent):
    return (_sub_panel(space, parent, "style", "Style", lambda layout, tree, scene: _draw_style(layout, tree.ink),
                       closed=True),
            _sub_panel(space, parent, "layers", "Ink Layers", lambda layout, tree, scene: _draw_layers(layout, tree)),
            _sub_panel(space, parent, "animation", "Animation", _draw_animation, closed=True))


classes = (VIEW3D_PT_blobtree_ink, *_sub_panels("VIEW_3D", "VIEW3D_PT_blobtree_ink"),
           NODE_PT_blobtree_ink, *_sub_panels("NODE_EDITOR", "NODE_PT_blobtree_ink"))
