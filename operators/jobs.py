"""Pipeline jobs from what Blender shows (the Blender side of every path that
illustrates): the eye from the scene camera or the viewport, the light from the scene's
lights, a request's region from the selection or the 3D cursor, the style and settings
from the tree; which layers of the ink a job leaves were drawn for another
viewpoint or model. The operators and the command line build their jobs here, so the same
scene gives the same job whichever path draws."""
import bpy
import numpy as np
from mathutils import Matrix, Vector

from .. import pipeline as PL
from ..agents import Region, Settings
from ..blackboard.board import FEATURE_KINDS
from ..blackboard.view import View
from ..grease_pencil import views
from ..model import Evaluator, fingerprint
from ..pipeline.job import SINGLE_LAYER, STYLE_LAYERS
from ..strokes.data import LAYER_OF_KIND, LAYERS
from .common import blobtrees, ink_name


def _world(obj, depsgraph):
    """An object's matrix in the scene (as ``depsgraph`` evaluates it, when given)."""
    return (obj.evaluated_get(depsgraph) if depsgraph is not None else obj).matrix_world


def placement(tree, depsgraph=None):
    """The matrix that places the tree's model in the scene: its preview object's (the
    artist moves the model by moving that object), else the identity."""
    obj = tree.preview_object
    return _world(obj, depsgraph).copy() if obj is not None else Matrix.Identity(4)


def to_model(matrix, point):
    """A scene point in the model's coordinates (``matrix``: the inverse placement)."""
    return None if point is None else tuple(matrix @ Vector(tuple(point)))


def direction_to_model(matrix, d):
    """A scene direction in the model's coordinates, unit length."""
    if d is None:
        return None
    v = np.array(matrix.to_3x3() @ Vector(tuple(d)), float)
    return tuple(v / np.linalg.norm(v))


def scale_of(matrix):
    """The most a placement matrix stretches a length: a model's radius in the scene is
    its own times this."""
    return max(v.length for v in matrix.to_3x3().col)


def attach(ink, tree):
    """The ink object follows its model: a child of the preview object, drawn in the
    model's coordinates, its own move, turn and scale locked (its lines are the model's
    where it stands: a click on the drawing selects the ink, and G then moves nothing)."""
    parent = tree.preview_object
    if ink.parent != parent:
        ink.parent = parent
    ink.matrix_parent_inverse = Matrix.Identity(4)
    ink.matrix_basis = Matrix.Identity(4)
    ink.lock_location = ink.lock_rotation = ink.lock_scale = (True, True, True)


def on_paper(context, tree):
    """Where the tree's Paper is on: the scene, the screen's 3D viewports and the
    preview on white paper (blobtree_nodes.settings.put_on_paper)."""
    if tree.ink.paper:
        from ..blobtree_nodes.settings import put_on_paper
        put_on_paper(tree, context)


def camera_eye(scene, depsgraph=None):
    """The scene camera's position, or None without a camera."""
    cam = scene.camera
    return None if cam is None else np.array(_world(cam, depsgraph).translation, float)


IN_CAMERA = 0.75            # less of a model than this share in the camera's frame: say so
CAMERA_SAMPLES = 400        # the preview's vertices that tell, at most


def off_camera(scene, tree):
    """A warning when the tree's preview (the model as the artist sees it) lies partly
    outside the scene camera's frame (less than IN_CAMERA of its vertices, an even
    sample of at most CAMERA_SAMPLES, in the frame and in front of the camera), else
    None (also without a camera or a preview)."""
    from bpy_extras.object_utils import world_to_camera_view
    cam, co = scene.camera, preview_points(tree)
    if cam is None or co is None:
        return None
    co = co[::max(1, len(co) // CAMERA_SAMPLES)]
    seen = np.array([tuple(world_to_camera_view(scene, cam, Vector(c))) for c in co.tolist()])
    inside = float(np.mean((seen[:, 2] > 0) & (seen[:, :2] >= 0).all(axis=1) & (seen[:, :2] <= 1).all(axis=1)))
    if inside >= IN_CAMERA:
        return None
    return (f"'{tree.name}' is {'outside' if inside == 0 else 'partly outside'} the scene camera's view: Frame "
            "Camera (beside From Camera) aims it at the model, or untick From Camera")


def preview_points(tree):
    """The vertices of the tree's preview mesh in the scene (n, 3): the model as the
    artist sees it; None without a preview."""
    obj = tree.preview_object
    if obj is None or obj.data is None or not len(obj.data.vertices):
        return None
    co = np.empty(3 * len(obj.data.vertices), np.float32)
    obj.data.vertices.foreach_get("co", co)
    m = np.array(obj.matrix_world, float)
    return co.reshape(-1, 3) @ m[:3, :3].T + m[:3, 3]


ORTHO_DISTANCE = 100.0      # an orthographic view's eye: this many model radii back along its direction


def viewport_eye(context, centre, radius):
    """The 3D viewport's eye, or None outside a 3D viewport. An orthographic view is
    drawn from an eye far back along its direction from the model's ``centre`` (``centre``
    and ``radius`` in the scene's coordinates; ORTHO_DISTANCE model radii back: its
    silhouettes are those of parallel rays to within a hundredth), so that panning or
    zooming it leaves the eye where it is."""
    rv3d = getattr(context, "region_data", None)
    if rv3d is None or not hasattr(rv3d, "view_matrix"):
        return None
    inv = rv3d.view_matrix.inverted()
    if rv3d.is_perspective:
        return np.array(inv.translation, float)
    back = np.array(inv.to_3x3() @ Vector((0.0, 0.0, 1.0)), float)       # the view looks along -z
    return np.asarray(centre, float) + ORTHO_DISTANCE * radius * back / np.linalg.norm(back)


def scene_light(scene, depsgraph=None):
    """The scene's light for a job: (direction, None) towards a sun, else (None,
    position) of the first other light, else (None, None): the pipeline lights the
    model from the viewer's upper left."""
    lights = [o for o in scene.objects if o.type == "LIGHT" and not o.hide_render]
    suns = [o for o in lights if o.data.type == "SUN"]
    if suns:
        d = np.array(_world(suns[0], depsgraph).to_3x3() @ Vector((0.0, 0.0, 1.0)), float)
        if np.linalg.norm(d) > 0:
            return tuple(d), None
    if lights:
        return None, tuple(np.array(_world(lights[0], depsgraph).translation, float))
    return None, None


def request_region(context, tree, inverse):
    """The region of a region request as the tree's settings say, in the model's
    coordinates (``inverse``: the inverse placement): the selection's bounds (or None:
    the whole model), or a sphere around the 3D cursor, its radius the region size times
    the model's radius (made by the pipeline: pipeline.Around)."""
    if tree.ink.region == "CURSOR":
        return PL.Around(to_model(inverse, context.scene.cursor.location), tree.ink.region_size)
    return selection_region(context, tree, inverse)


def selection_region(context, tree, inverse):
    """The bounds of the selected objects that can mark a region (not Grease Pencil
    objects, not the tree's own preview mesh) in the model's coordinates, or None: the
    whole model."""
    own = tree.preview_object
    sel = [o for o in getattr(context, "selected_objects", None) or []
           if o.type != "GREASEPENCIL" and (own is None or o.name != own.name)]
    if not sel:
        return None
    pts = np.array([inverse @ o.matrix_world @ Vector(c) for o in sel for c in o.bound_box])
    return Region(box=(pts.min(0), pts.max(0)))


def job(model, scene, style, settings, requests, seed, eye=None, seconds=None, inverse=None, depsgraph=None,
        occluders=()):
    """A pipeline job for a model seen by the scene: ``eye`` where given (the
    viewport's), else the scene camera's, else (the pipeline's) a three-quarter view
    framing the model; eye and light taken into the model's coordinates by ``inverse``
    (the inverse placement; default the identity); objects as ``depsgraph`` evaluates
    them, when given; ``occluders``: the scene's other models that can hide its lines
    (:func:`occluders`). Nothing is sampled here: that is the pipeline's work, on its
    worker."""
    inverse = Matrix.Identity(4) if inverse is None else inverse
    if eye is None:
        eye = camera_eye(scene, depsgraph)
    light, light_at = scene_light(scene, depsgraph)
    eye = to_model(inverse, eye)
    return PL.Job(model, None if eye is None else View(eye=np.array(eye)), direction_to_model(inverse, light), style,
                  tuple(requests), seed, settings, seconds, to_model(inverse, light_at), tuple(occluders))


def in_scene(tree, scene):
    """Whether the tree is drawn in the scene: its ink, or its preview, is in it (a tree
    kept only by its fake user is not)."""
    return any(o is not None and scene in o.users_scene
               for o in (bpy.data.objects.get(ink_name(tree)), tree.preview_object))


def rendered(tree, scene):
    """Whether the tree shows in the scene's renders: its ink is in the scene and not
    hidden from renders, or its preview mesh is rendered, or it has no ink yet but is
    in the scene with Illustrate Rendered Frames on (a render draws it then)."""
    ink, preview = bpy.data.objects.get(ink_name(tree)), tree.preview_object
    if ink is not None and scene in ink.users_scene and not ink.hide_render:
        return True
    if preview is not None and scene in preview.users_scene and not preview.hide_render:
        return True
    return ink is None and tree.ink.render_frames and in_scene(tree, scene)


def occluders(scene, tree, depsgraph=None, compiler=None):
    """The scene's other models that can hide the tree's lines: (Model, matrix from the
    tree's model coordinates into the other's) of each other tree that shows in renders
    (:func:`rendered`), as ``depsgraph`` evaluates them (default: the context's); and
    the names of those left out because their tree does not compile (the caller says
    so). ``compiler(tree, mark)``: how a tree is compiled (default: compile_tree)."""
    from ..blobtree_nodes.animation import DriverError
    from ..blobtree_nodes.compile import TreeError, compile_tree
    if compiler is None:
        def compiler(other, mark):
            return compile_tree(other, mark, depsgraph)
    solids, broken = [], []
    for other, into, _ in _others(scene, tree, depsgraph):
        try:
            model = compiler(other, mark=False)
        except (TreeError, DriverError):
            broken.append(other.name)
            continue
        solids.append((model, into))
    return tuple(solids), broken


def _others(scene, tree, depsgraph=None):
    """(tree, the matrix from the tree's model coordinates into its, and back) of each
    other tree of the scene that shows in renders (:func:`rendered`)."""
    to_scene = placement(tree, depsgraph)
    for other in blobtrees():
        if other != tree and rendered(other, scene):
            place = placement(other, depsgraph)
            yield (other, np.array(place.inverted_safe() @ to_scene, float),
                   np.array(to_scene.inverted_safe() @ place, float))


def hiders_now(scene, tree, eye, keys=None, depsgraph=None):
    """{name: (key, between)} of the scene's other models that show in renders, as their
    previews show them and where they stand now (pipeline.hiding.hiders' record of a
    drawing, made without compiling them), for the tree's model seen from ``eye`` (its
    coordinates); None where that is not known (a preview not shown). A tree whose
    nodes show an error hides nothing (a drawing leaves it out). ``keys``: {model name:
    model.fingerprint} of the models as compiled (those left out do not compile), in
    place of their previews'; ``depsgraph``: as :func:`occluders`."""
    from ..blobtree_nodes import preview
    from ..blobtree_nodes.panels import nodes_with_errors
    from ..pipeline import hiding
    if tree.preview_object is None:
        return None
    drawn = hiding.sphere_of(_box(tree.preview_object), np.eye(4))
    items = []
    for other, into, back in _others(scene, tree, depsgraph):
        name = other.model_name or other.name
        if (keys is None and nodes_with_errors(other)) or (keys is not None and name not in keys):
            continue
        key = preview.shown_model(other) if keys is None else keys[name]
        if key is None or other.preview_object is None:
            return None
        near = hiding.between(np.asarray(eye, float), drawn, hiding.sphere_of(_box(other.preview_object), back))
        items.append((name, (hiding.place_key(key, into), near)))
    return hiding.named(items)


def moved_hiders(obj, job, layers, frame, scene, tree, depsgraph=None):
    """Those of ``layers`` of the ink object shown on ``frame`` drawn before the models
    in front of them moved or changed (pipeline.hiding.changed), the job's occluders
    taken as compiled (and placed as ``depsgraph`` evaluates them: as :func:`occluders`)."""
    keys = {m.name: fingerprint(m) for m in (x.model if isinstance(x, Evaluator) else x for x, _ in job.occluders)}
    return views.other_hiders(obj, layers, frame, lambda at: hiders_now(scene, tree, at, keys, depsgraph))


def _box(obj):
    corners = np.array([tuple(c) for c in obj.bound_box], float)
    return corners.min(axis=0), corners.max(axis=0)


def hidden_by_note(broken):
    """What a run says of the trees that could hide its lines but do not compile (None
    when there are none)."""
    if not broken:
        return None
    names = ", ".join(f"'{n}'" for n in broken)
    if len(broken) == 1:
        return f"{names} hides no lines: its tree is broken"
    return f"{names} hide no lines: their trees are broken"


def tree_settings(ink):
    """The sampling settings of a tree's illustration settings."""
    return Settings(resolution=ink.grid_resolution, agents=ink.agents, lod=ink.lod, seed=ink.seed,
                    kinds=tuple(k for k in FEATURE_KINDS if getattr(ink, f"line_{k}")))


def drawn_elsewhere(obj, job, frame, centre, radius, scene, tree):
    """{layer: why} of the layers of the ink object ``obj`` shown on ``frame`` that
    ``job`` leaves as they are but that were drawn for another model than the job's
    (views.MODEL), or for an eye that does not see the model as the job's does
    (views.VIEWPOINT; the model's ``centre`` and ``radius`` place its three-quarter eye,
    without a view), or before the models in front of it (the job's occluders, in the
    ``tree``'s ``scene``) moved or changed (HIDDEN). The single strokes are the
    artist's own, from wherever they were drawn."""
    eye = PL.view_eye(job.view, centre, radius)
    mine = set(job.owned_layers()) | set(job.appended_layers()) | {SINGLE_LAYER}
    left = [n for n in LAYERS if n not in mine]
    out = views.unfit(obj, left, frame, eye, centre, model_key(job))
    hidden = moved_hiders(obj, job, [n for n in left if n not in out], frame, scene, tree)
    return {**out, **dict.fromkeys(hidden, HIDDEN)}


def model_key(job):
    """The key (model.fingerprint) of a job's model, as its result records it."""
    return fingerprint(job.model.model if isinstance(job.model, Evaluator) else job.model)


def traced_layers(job):
    """The outline layers a Trace Feature Outlines with the job's settings draws."""
    return [LAYER_OF_KIND[k] for k in job.settings.kinds]


ANOTHER_LOOK = "look"        # why a look clears a layer: its style draws none (another look's strokes)
HIDDEN = "hidden"            # ... or why a layer does not fit: drawn before the models in front of it moved
WHY = {views.VIEWPOINT: ("drawn for another viewpoint", "for this one"),
       views.MODEL: ("drawn before the model changed", "again"),
       HIDDEN: ("drawn before the models in front of it moved or changed", "again"),
       ANOTHER_LOOK: ("not in this look", "")}


def elsewhere_note(unfit, job):
    """What a run says of the layers it left that were drawn for another viewpoint or
    model (``unfit``: {layer: why}): which request draws them for this one, or, for a
    layer the settings or the style no longer draw, that Ink Layers clears it (None
    when there are none)."""
    placed = [STYLE_LAYERS[k] for k in job.style.stroke_switches()]
    say = []
    for why, (drawn, redrawn) in ((w, WHY[w]) for w in (views.VIEWPOINT, views.MODEL, HIDDEN)):
        layers = [n for n, w in unfit.items() if w == why]
        traced = [n for n in layers if n in traced_layers(job)]
        for names, what in ((traced, f"Trace Feature Outlines draws {{}} {redrawn}"),
                            ([n for n in layers if n in placed], f"Place Strokes draws {{}} {redrawn}"),
                            ([n for n in layers if n not in traced_layers(job) and n not in placed],
                             "switched off, Ink Layers clears {}")):
            if names:
                them = "it" if len(names) == 1 else "them"
                say.append(f"{', '.join(names)} {drawn}: {what.format(them)}")
    return "; ".join(say) or None


def cleared_note(unfit):
    """What a look says of the layers it cleared (``unfit``: {layer: why}, as
    :func:`elsewhere_note`'s), or None."""
    say = []
    for why, (drawn, _) in WHY.items():
        names = [n for n, w in unfit.items() if w == why]
        if names:
            them = "it" if len(names) == 1 else "them"
            say.append(f"{', '.join(names)} cleared: {drawn} (Ctrl+Z brings {them} back)")
    return "; ".join(say) or None
