"""Frame Camera: the scene camera moved, its direction kept, until the tree's model
(with Every Model, every BlobTree model in the scene) fills its frame with the framing
margin (an orthographic one also zoomed), so that a From Camera run and a render see
the whole model. Without a scene camera one is made, looking from the three-quarter
view. One undo step.

    bpy.ops.blobtree_ink.frame_camera(tree_name="heart", every_model=True)
"""
import bpy
import numpy as np
from mathutils import Vector

from .. import pipeline as PL
from ..blobtree_nodes.compile import TreeError, compile_document
from ..grease_pencil import render as OUT
from ..grease_pencil.scene import CAMERA, look_rotation
from ..model import Evaluator
from ..pipeline.framing import LENS, SENSOR
from . import jobs
from .common import blobtrees, context_tree


class BLOBTREE_INK_OT_frame_camera(bpy.types.Operator):
    """Move the scene camera, its direction kept, until it frames the BlobTree's model (or make one)"""
    bl_idname = "blobtree_ink.frame_camera"
    bl_label = "Frame Camera"
    bl_options = {"REGISTER", "UNDO"}

    tree_name: bpy.props.StringProperty(name="Tree", options={"SKIP_SAVE"},
                                        description="The BlobTree node tree (empty: the active one)")
    every_model: bpy.props.BoolProperty(name="Every Model", default=False,
                                        description="Frame every BlobTree model in the scene, not only this one")

    def execute(self, context):
        scene = context.scene
        try:
            tree = context_tree(context, self.tree_name)
            trees = [t for t in blobtrees() if t == tree or jobs.in_scene(t, scene)] if self.every_model else [tree]
            models = [_in_scene(t) for t in trees]
        except (TreeError, PL.NothingToDraw, LookupError) as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        points = np.concatenate([p for _, _, p in models])
        if len(models) == 1:                 # one model: about its own centre
            centre, radius, _ = models[0]
        else:                              # several: about the middle of them all
            centre = 0.5 * (points.min(axis=0) + points.max(axis=0))
            radius = float(np.linalg.norm(points - centre, axis=1).max())
        cam = scene.camera
        if cam is None:
            cam = _new_camera(scene, centre, radius)
        elif cam.type != "CAMERA":
            self.report({"ERROR"}, f"the scene camera '{cam.name}' is not a camera object: make a camera "
                                   "the scene's (Ctrl+Numpad 0 on one)")
            return {"CANCELLED"}
        frame(scene, cam, centre, points)
        moved = f"'{cam.name}' frames " + ", ".join(f"'{t.name}'" for t in trees)
        held = held_by(cam)
        if held:
            self.report({"WARNING"}, f"{moved}, but its {held} may move it back: key its new place (I) or "
                                     "change what moves it")
        else:
            self.report({"INFO"}, moved)
        return {"FINISHED"}


def _in_scene(tree):
    """The tree's model in the scene: its centre, its radius and the points a frame must
    hold (:func:`outline_points`); raises TreeError for a tree that does not compile,
    NothingToDraw for an empty model."""
    model, _ = compile_document(tree)
    centre, radius = PL.bounds(Evaluator(model))
    place = jobs.placement(tree)
    centre = np.array(place @ Vector(tuple(centre)), float)
    radius *= jobs.scale_of(place)
    return centre, radius, outline_points(tree, centre, radius)


def outline_points(tree, centre, radius):
    """Scene points whose frame holds the model: its preview's vertices (the model as
    the artist sees it), or without a preview the corners of the cube about its
    bounding sphere."""
    points = jobs.preview_points(tree)
    if points is not None:
        return points
    cube = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], float)
    return centre + radius * cube


NEAR = 0.1                  # the camera's near clip at most this share of the model's reach from its centre
FAR = 2.0                   # its far clip at least this many times its distance from the farthest point


def frame(scene, cam, centre, points):
    """Move the camera ``cam``, its direction and lens shift kept, onto the line through
    ``centre`` and its frame's centre, where the scene's render frame holds ``points``
    (n, 3) with the framing margin: a perspective camera at the nearest distance that
    does, an orthographic one zoomed to it (and set back far enough to see them all)."""
    world = cam.matrix_world.copy()
    lens = OUT.lens(scene, cam)            # the frame one unit ahead (orthographic: at any depth)
    half, mid = np.asarray(lens.half), np.asarray(lens.centre)
    rel = (np.asarray(points, float) - centre) @ lens.axes           # the points about the centre, in camera axes
    reach = float(np.linalg.norm(rel, axis=1).max())
    data = cam.data
    in_front = float(rel[:, 2].max()) + data.clip_start + NEAR * reach          # every point past the near clip
    if lens.ortho:
        zoom = PL.ortho_fit(rel, half)
        data.ortho_scale *= zoom
        back = max(float(np.dot(lens.eye - centre, lens.axes[:, 2])), in_front)
        place = np.array([-zoom * mid[0], -zoom * mid[1], back])
    else:
        back = max(PL.perspective_fit(rel, half, mid), in_front)
        place = back * np.array([-mid[0], -mid[1], 1.0])
    world.translation = Vector(tuple(centre + lens.axes @ place))
    cam.matrix_world = world
    data.clip_start = min(data.clip_start, NEAR * reach)
    data.clip_end = max(data.clip_end, FAR * (float(np.linalg.norm(place)) + reach))


def _new_camera(scene, centre, radius):
    """A camera for a scene without one, looking at the model from the three-quarter view."""
    cam = bpy.data.objects.new(CAMERA, bpy.data.cameras.new(CAMERA))
    scene.collection.objects.link(cam)
    cam.data.lens, cam.data.sensor_width = LENS, SENSOR
    eye = PL.three_quarter_eye(centre, radius)
    cam.location = tuple(float(x) for x in eye)
    cam.rotation_euler = look_rotation(centre - eye)
    scene.camera = cam
    bpy.context.view_layer.update()              # its world matrix, which framing reads
    return cam


def held_by(cam):
    """What may put the camera back where it was (its animation, drivers, constraints
    or a parent's animation), or ''."""
    held = ["animation"] if _animated(cam) else []
    if any(c.enabled for c in cam.constraints):
        held.append("constraints")
    if cam.parent is not None and _animated(cam.parent):
        held.append("parent's animation")
    return " and ".join(held)


def _animated(obj):
    """Whether an object has an action or drivers."""
    anim = obj.animation_data
    return anim is not None and (anim.action is not None or len(anim.drivers) > 0)


classes = (BLOBTREE_INK_OT_frame_camera,)
