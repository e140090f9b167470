"""Where a model sits in the scene: an imported model lands beside the others, and its
preview object places it (moving the preview moves the model and its ink)."""
import bpy
import numpy as np
import pytest
from aimed_camera import aimed_camera
from mathutils import Vector


def world_box(obj):
    c = np.array([obj.matrix_world @ Vector(v) for v in obj.bound_box])
    return c.min(0), c.max(0)


def test_an_imported_model_lands_beside_the_others(example):
    bpy.ops.blobtree_ink.import_json(filepath=example("pear"), preview=True)
    bpy.ops.blobtree_ink.import_json(filepath=example("jug"), preview=True)
    bpy.ops.blobtree_ink.import_json(filepath=example("torus"), preview=True)
    boxes = [world_box(bpy.data.node_groups[n].preview_object) for n in ("pear", "jug", "torus")]
    for (lo_a, hi_a), (lo_b, hi_b) in zip(boxes, boxes[1:]):
        assert lo_b[0] > hi_a[0]                       # side by side along x, not on top of each other
    assert bpy.context.view_layer.objects.active == bpy.data.node_groups["torus"].preview_object


def test_moving_the_preview_moves_the_model_and_its_ink(example):
    bpy.ops.blobtree_ink.import_json(filepath=example("sphere"), preview=True)
    tree = bpy.data.node_groups["sphere"]
    tree.ink.grid_resolution = 10
    tree.preview_object.location = (5.0, 1.0, -2.0)
    tree.preview_object.rotation_euler = (0.3, 0.0, 0.7)
    cam = aimed_camera((5.0, -4.0, -1.0), (5.0, 1.0, -2.0))
    assert bpy.ops.blobtree_ink.illustrate(tree_name="sphere", request="OUTLINES") == {"FINISHED"}
    ink = bpy.data.objects["sphere Ink"]
    assert ink.parent == tree.preview_object
    # the ink cannot be moved off its model (a click on the drawing selects it: G moves nothing)
    assert all(all(lock) for lock in (ink.lock_location, ink.lock_rotation, ink.lock_scale))
    strokes = ink.data.layers["Silhouette"].frames[0].drawing.strokes
    assert len(strokes) == 1
    world = np.array([ink.matrix_world @ Vector(p.position) for p in strokes[0].points])
    r = 0.4543
    assert np.abs(np.linalg.norm(world - [5.0, 1.0, -2.0], axis=1) - r).max() < 1e-4   # on the moved sphere
    eye = np.array(cam.location)
    n = (world - [5.0, 1.0, -2.0]) / r
    assert np.abs(np.einsum("ij,ij->i", n, world - eye)).max() < 1e-3 * np.linalg.norm(eye)   # its silhouette


def test_a_followed_object_keeps_its_place_in_the_scene_when_the_model_moves(example):
    """A primitive that follows an Empty sits at the Empty's place in the scene, parent
    and constraint included, wherever the model's preview is."""
    from importlib import import_module
    comp = import_module("bl_ext.user_default.blobtree_ink.blobtree_nodes.compile")
    bpy.ops.blobtree_ink.import_json(filepath=example("sphere"), preview=True)
    tree = bpy.data.node_groups["sphere"]
    point = next(n for n in tree.nodes if getattr(n, "kind", "") == "point")
    parent = bpy.data.objects.new("Parent", None)
    empty = bpy.data.objects.new("Target", None)
    for o in (parent, empty):
        bpy.context.scene.collection.objects.link(o)
    empty.parent = parent
    parent.location = (1.0, 2.0, 3.0)
    empty.location = (0.5, 0.0, 0.0)                 # in the parent's space: (1.5, 2, 3) in the scene
    point.center_object = empty
    tree.preview_object.location = (10.0, 0.0, 0.0)
    bpy.context.view_layer.update()
    model = comp.compile_tree(tree)
    assert tuple(model.root.center) == (-8.5, 2.0, 3.0)      # the scene's (1.5, 2, 3) in the model's space
    con = empty.constraints.new("LIMIT_LOCATION")            # a constraint: x at most 1.2 in the scene
    con.use_max_x, con.max_x = True, 1.2
    bpy.context.view_layer.update()
    assert comp.compile_tree(tree).root.center[0] == pytest.approx(-8.8, abs=1e-6)


def test_a_model_outside_the_camera_says_so_when_drawn_from_camera(ext, example):
    """From Camera draws the model as the camera sees it: a model the camera sees only
    in part, or not at all (an import placed beside the first model), gets a warning
    saying what to do; one in the frame does not."""
    from importlib import import_module
    jobs = import_module(f"{ext.__name__}.operators.jobs")
    bpy.ops.blobtree_ink.import_json(filepath=example("sphere"), preview=True)
    tree = bpy.data.node_groups["sphere"]
    sc = bpy.context.scene
    cam = aimed_camera((0.0, -2.5, 0.0), (0.0, 0.0, 0.0))
    assert jobs.off_camera(sc, tree) is None                      # filling most of the frame's height
    cam.location = (0.0, -6.0, 0.0)
    bpy.context.view_layer.update()
    assert jobs.off_camera(sc, tree) is None                      # in the middle of the frame
    tree.preview_object.location = (4.0, 0.0, 0.0)                # beside it: out of the frame
    bpy.context.view_layer.update()
    note = jobs.off_camera(sc, tree)
    assert note == "'sphere' is outside the scene camera's view: Frame Camera (beside From Camera) aims it at " \
                   "the model, or untick From Camera"
    tree.preview_object.location = (2.0, 0.0, 0.0)                # cut by the frame's edge
    bpy.context.view_layer.update()
    assert "'sphere' is partly outside the scene camera's view" in jobs.off_camera(sc, tree)
    tree.preview_object.location = (0.0, 12.0, 0.0)               # in line, but far: still seen
    bpy.context.view_layer.update()
    assert jobs.off_camera(sc, tree) is None
    tree.preview_object.location = (0.0, -12.0, 0.0)             # behind the camera
    bpy.context.view_layer.update()
    assert jobs.off_camera(sc, tree) is not None
    sc.camera = None
    assert jobs.off_camera(sc, tree) is None


def in_frame(cam, obj):
    """The preview's vertices in the camera's normalised frame (x, y in 0..1 inside it)."""
    from bpy_extras.object_utils import world_to_camera_view
    sc = bpy.context.scene
    return np.array([tuple(world_to_camera_view(sc, cam, obj.matrix_world @ v.co)) for v in obj.data.vertices])


def test_frame_camera_aims_the_scene_camera_at_a_model_beside_the_first(ext, example):
    """A second import lands beside the first, out of the camera's view: Frame Camera
    moves the camera along its line of sight until the model fills the frame with the
    command line's margin (a perspective camera backs off, an orthographic one zooms),
    its direction kept; without a camera it makes one; a broken tree changes nothing."""
    from importlib import import_module
    jobs = import_module(f"{ext.__name__}.operators.jobs")
    bpy.ops.blobtree_ink.import_json(filepath=example("pear"), preview=True)
    bpy.ops.blobtree_ink.import_json(filepath=example("sphere"), preview=True)
    tree, sc = bpy.data.node_groups["sphere"], bpy.context.scene
    sc.render.resolution_x, sc.render.resolution_y = 1920, 1080
    cam = aimed_camera((-6.0, -8.0, 1.0), (-6.0, 0.0, 0.5))          # looking past the models
    ahead = cam.matrix_world.to_3x3() @ Vector((0.0, 0.0, -1.0))
    assert jobs.off_camera(sc, tree) is not None
    assert bpy.ops.blobtree_ink.frame_camera(tree_name="sphere") == {"FINISHED"}
    bpy.context.view_layer.update()
    assert jobs.off_camera(sc, tree) is None
    assert (cam.matrix_world.to_3x3() @ Vector((0.0, 0.0, -1.0))).angle(ahead) < 1e-6     # its direction kept
    seen = in_frame(cam, tree.preview_object)
    assert (seen[:, :2] > 0).all() and (seen[:, :2] < 1).all()
    # the sphere fills the frame's height, less the margin (its radius over the frame's half-height is 1/MARGIN)
    tall = np.ptp(seen[:, 1])
    assert 0.80 < tall < 1 / 1.15 + 0.01, tall
    # a lens shift and a portrait frame fitted on its height: the model framed all the same
    sc.render.resolution_x, sc.render.resolution_y = 1080, 1920
    cam.data.sensor_fit, cam.data.shift_x, cam.data.shift_y = "VERTICAL", 0.2, -0.1
    assert bpy.ops.blobtree_ink.frame_camera(tree_name="sphere") == {"FINISHED"}
    bpy.context.view_layer.update()
    seen = in_frame(cam, tree.preview_object)
    assert (seen[:, :2] > 0).all() and (seen[:, :2] < 1).all()
    assert 0.80 < np.ptp(seen[:, 0]) < 1 / 1.15 + 0.01                 # the narrow side, the width, decides
    assert abs(seen[:, 0].mean() - 0.5) < 0.02 and abs(seen[:, 1].mean() - 0.5) < 0.02       # centred
    sc.render.resolution_x, sc.render.resolution_y = 1920, 1080
    cam.data.sensor_fit, cam.data.shift_x, cam.data.shift_y = "AUTO", 0.0, 0.0
    # orthographic: zoomed to the same share of the frame
    cam.data.type = "ORTHO"
    cam.data.ortho_scale = 100.0
    assert bpy.ops.blobtree_ink.frame_camera(tree_name="sphere") == {"FINISHED"}
    bpy.context.view_layer.update()
    seen = in_frame(cam, tree.preview_object)
    assert (seen[:, :2] > 0).all() and (seen[:, :2] < 1).all() and 0.80 < np.ptp(seen[:, 1]) < 0.88
    # no scene camera: one is made, looking at the model
    sc.camera = None
    assert bpy.ops.blobtree_ink.frame_camera(tree_name="sphere") == {"FINISHED"}
    bpy.context.view_layer.update()
    assert sc.camera is not None and sc.camera is not cam and sc.camera.type == "CAMERA"
    assert jobs.off_camera(sc, tree) is None
    # a camera whose keys (or constraints) put it back is framed, and the report says so
    fc = import_module(f"{ext.__name__}.operators.frame_camera")
    assert fc.held_by(sc.camera) == ""
    sc.camera.keyframe_insert("location")
    sc.camera.constraints.new("TRACK_TO")
    assert fc.held_by(sc.camera) == "animation and constraints"
    # a tree that does not compile: said, the camera left where it is
    before = sc.camera.matrix_world.copy()
    [n for n in tree.nodes if hasattr(n, "radius")][0].radius = 0.0
    with pytest.raises(RuntimeError, match="Radius must be > 0"):
        bpy.ops.blobtree_ink.frame_camera(tree_name="sphere")
    assert sc.camera.matrix_world == before
    with pytest.raises(RuntimeError, match="no BlobTree node tree named 'nope'"):
        bpy.ops.blobtree_ink.frame_camera(tree_name="nope")


def _behind(points, eye, centre, radius):
    """Which points lie behind a ball (``centre``, ``radius``) as the eye sees them."""
    d = (points - eye) / np.linalg.norm(points - eye, axis=1)[:, None]
    c = np.asarray(centre) - eye
    return (np.linalg.norm(c - (d @ c)[:, None] * d, axis=1) < radius) & (d @ c < np.linalg.norm(points - eye, axis=1))


def test_another_model_in_front_hides_the_lines_behind_it(example):
    """Two spheres, one in front of the other as the camera sees them: the silhouette of
    the one behind is drawn only where the one in front leaves it in sight, as a render
    (where the previews are not drawn) shows it; a model hidden from renders hides
    nothing, and one whose tree is broken is named."""
    bpy.ops.blobtree_ink.import_json(filepath=example("sphere"), preview=True)
    back = bpy.data.node_groups["sphere"]
    bpy.ops.blobtree_ink.import_json(filepath=example("sphere"), preview=True)
    front = next(t for t in bpy.data.node_groups if t != back)
    front.preview_object.location = (0.3, -2.5, 0.0)
    back.preview_object.location = (0.0, 0.0, 0.0)
    cam = aimed_camera((0.0, -8.0, 0.0), (0.0, 0.0, 0.0))
    eye = np.array(cam.location)
    r = 0.4543

    def drawn():
        assert bpy.ops.blobtree_ink.illustrate(tree_name="sphere", request="OUTLINES") == {"FINISHED"}
        ink = bpy.data.objects["sphere Ink"]
        return np.array([ink.matrix_world @ Vector(p.position)
                         for s in ink.data.layers["Silhouette"].frames[0].drawing.strokes for p in s.points])

    # the front model's solid, in the scene: its preview's vertices tell where it stands
    co = np.array([front.preview_object.matrix_world @ v.co for v in front.preview_object.data.vertices])
    centre, reach = co.mean(0), 0.98 * np.linalg.norm(co - co.mean(0), axis=1).min()
    hidden = drawn()
    assert len(hidden) > 20 and not _behind(hidden, eye, centre, reach).any()
    assert bpy.ops.blobtree_ink.illustrate(tree_name=front.name, request="OUTLINES") == {"FINISHED"}
    ink = bpy.data.objects[f"{front.name} Ink"]               # the front model's own ink, hidden from renders
    assert ink != bpy.data.objects["sphere Ink"]
    ink.hide_render = True
    seen = drawn()
    assert _behind(seen, eye, centre, reach).sum() > 5                  # the whole circle again
    ink.hide_render = False
    node = next(n for n in front.nodes if getattr(n, "kind", "") == "point")
    node.radius = -1.0                                                  # a broken tree hides nothing, and says so
    from importlib import import_module
    jobs = import_module("bl_ext.user_default.blobtree_ink.operators.jobs")
    solids, broken = jobs.occluders(bpy.context.scene, back)
    assert solids == () and broken == [front.name]
    assert jobs.hidden_by_note(broken) == f"'{front.name}' hides no lines: its tree is broken"


def test_an_orthographic_viewport_sees_from_its_direction_wherever_it_is_panned(ext):
    """jobs.viewport_eye: a perspective viewport's eye is where it stands; an
    orthographic one's lies ORTHO_DISTANCE radii back from the model's centre along the
    view, so panning it (the view's own place) does not make it another viewpoint."""
    from types import SimpleNamespace
    from mathutils import Euler, Matrix
    jobs = ext.operators.jobs
    turn = Euler((0.6, 0.0, 0.8)).to_matrix().to_4x4()          # the view's own axes in the scene

    def viewport(at, perspective):
        view_to_scene = Matrix.Translation(at) @ turn
        return SimpleNamespace(region_data=SimpleNamespace(view_matrix=view_to_scene.inverted(),
                                                           is_perspective=perspective))
    centre, radius = np.array([1.0, 2.0, 3.0]), 0.5
    back = np.array(turn.to_3x3() @ Vector((0.0, 0.0, 1.0)))
    eyes = [jobs.viewport_eye(viewport(at, False), centre, radius) for at in [(0, 0, 0), (4, -2, 7)]]
    np.testing.assert_allclose(eyes[0], eyes[1], atol=1e-5)
    np.testing.assert_allclose(eyes[0], centre + jobs.ORTHO_DISTANCE * radius * back, atol=1e-4)
    np.testing.assert_allclose(jobs.viewport_eye(viewport((4, -2, 7), True), centre, radius), [4, -2, 7], atol=1e-5)
    assert jobs.viewport_eye(SimpleNamespace(), centre, radius) is None        # no 3D viewport


def test_frame_camera_on_every_model_frames_them_all(ext, example):
    """Every Model: the camera frames every BlobTree model in the scene together, its
    direction kept; a model not in the scene does not count."""
    bpy.ops.blobtree_ink.import_json(filepath=example("pear"), preview=True)
    bpy.ops.blobtree_ink.import_json(filepath=example("sphere"), preview=True)
    pear, sphere, sc = bpy.data.node_groups["pear"], bpy.data.node_groups["sphere"], bpy.context.scene
    sc.render.resolution_x, sc.render.resolution_y = 1920, 1080
    cam = aimed_camera((-6.0, -8.0, 1.0), (-6.0, 0.0, 0.5))
    assert bpy.ops.blobtree_ink.frame_camera(tree_name="sphere") == {"FINISHED"}
    bpy.context.view_layer.update()
    assert not (in_frame(cam, pear.preview_object)[:, :2] > 0).all()        # the one model: the pear left out
    assert bpy.ops.blobtree_ink.frame_camera(tree_name="sphere", every_model=True) == {"FINISHED"}
    bpy.context.view_layer.update()
    both = np.concatenate([in_frame(cam, t.preview_object) for t in (pear, sphere)])
    assert (both[:, :2] > 0).all() and (both[:, :2] < 1).all()
    assert np.ptp(both[:, 0]) > 0.8 or np.ptp(both[:, 1]) > 0.8               # together they fill the frame
    bpy.data.node_groups.new("loose", "BlobTreeInkNodeTree")                  # in no scene: left out, no error
    assert bpy.ops.blobtree_ink.frame_camera(tree_name="sphere", every_model=True) == {"FINISHED"}
