"""Frame Camera: the scene camera moved along its own line of sight (an orthographic
one also zoomed) until the tree's model fills its frame as the command line's camera
frames it, so that a From Camera run and a render see the whole model. Without a scene
camera one is made, looking from the three-quarter view. One undo step.

    bpy.ops.blobtree_ink.frame_camera(tree_name="heart")
"""
import bpy
import numpy as np
from mathutils import Vector

from .. import pipeline as PL
from ..blobtree_nodes.compile import TreeError, compile_document
from ..grease_pencil.scene import CAMERA, look_rotation
from ..model import Evaluator
from ..pipeline.framing import LENS, SENSOR
from . import jobs
from .common import context_tree


class BLOBTREE_INK_OT_frame_camera(bpy.types.Operator):
    """Move the scene camera along its line of sight until it frames the BlobTree's model (or make one)"""
    bl_idname = "blobtree_ink.frame_camera"
    bl_label = "Frame Camera"
    bl_options = {"REGISTER", "UNDO"}

    tree_name: bpy.props.StringProperty(name="Tree", options={"SKIP_SAVE"},
                                        description="The BlobTree node tree (empty: the active one)")

    def execute(self, context):
        try:
            tree = context_tree(context, self.tree_name)
            model, _ = compile_document(tree)
            centre, radius = PL.bounds(Evaluator(model))
        except (TreeError, PL.NothingToDraw, LookupError) as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        place = jobs.placement(tree)
        centre = np.array(place @ Vector(tuple(centre)), float)
        radius *= max(v.length for v in place.to_3x3().col)
        scene = context.scene
        cam = scene.camera
        if cam is None:
            cam = _new_camera(scene, centre, radius)
        elif cam.type != "CAMERA":
            self.report({"ERROR"}, f"the scene camera '{cam.name}' is not a camera object: make a camera "
                                   "the scene's (Ctrl+Numpad 0 on one)")
            return {"CANCELLED"}
        frame(scene, cam, centre, outline_points(tree, centre, radius))
        moved = f"'{cam.name}' frames '{tree.name}'"
        held = held_by(cam)
        if held:
            self.report({"WARNING"}, f"{moved}, but its {held} may move it back: key its new place (I) or "
                                     "change what moves it")
        else:
            self.report({"INFO"}, moved)
        return {"FINISHED"}


def outline_points(tree, centre, radius):
    """Scene points whose frame holds the model: its preview's vertices (the model as
    the artist sees it), or without a preview the corners of the cube about its
    bounding sphere."""
    obj = tree.preview_object
    if obj is not None and obj.data is not None and len(obj.data.vertices):
        co = np.empty(3 * len(obj.data.vertices), np.float32)
        obj.data.vertices.foreach_get("co", co)
        m = np.array(obj.matrix_world, float)
        return co.reshape(-1, 3) @ m[:3, :3].T + m[:3, 3]
    cube = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], float)
    return centre + radius * cube


def frame(scene, cam, centre, points):
    """Put the camera ``cam`` on its line of sight through ``centre`` (its direction
    kept) where the scene's render frame holds ``points`` (n, 3) with the command line's
    margin: a perspective camera at the nearest distance that does, an orthographic one
    zoomed to it (and set back far enough to see them all)."""
    world = cam.matrix_world.copy()
    axes = np.array(world.to_3x3().normalized(), float)              # columns: right, up, backwards
    rel = (np.asarray(points, float) - centre) @ axes                 # the points about the centre, in camera axes
    side, beyond = np.abs(rel[:, :2]), -rel[:, 2]                     # off the line of sight; depth past the centre
    corners = np.array([tuple(v) for v in cam.data.view_frame(scene=scene)], float)
    half = 0.5 * np.ptp(corners[:, :2], axis=0)                       # the frame's half width and height
    reach = float(np.linalg.norm(rel, axis=1).max())
    in_front = float(cam.data.clip_start - beyond.min() + 0.1 * reach)   # every point past the near clip
    if cam.data.type == "ORTHO":
        cam.data.ortho_scale *= PL.MARGIN * float((side / half).max())
        distance = max(float(np.dot(np.array(world.translation) - centre, axes[:, 2])), in_front)
    else:
        tan_half = half / float(np.abs(corners[:, 2]).max())
        # a point at depth d past the centre is framed from t back when its offset <= (t + d) tan / MARGIN
        distance = max(float(((PL.MARGIN * side / tan_half).max(axis=1) - beyond).max()), in_front)
    world.translation = Vector(tuple(centre + distance * axes[:, 2]))
    cam.matrix_world = world
    data = cam.data
    data.clip_start = min(data.clip_start, 0.1 * reach)
    data.clip_end = max(data.clip_end, 2 * (distance + reach))


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
    held = []
    if cam.animation_data is not None and (cam.animation_data.action is not None or cam.animation_data.drivers):
        held.append("animation")
    if any(c.enabled for c in cam.constraints):
        held.append("constraints")
    if cam.parent is not None and cam.parent.animation_data is not None:
        held.append("parent's animation")
    return " and ".join(held)


classes = (BLOBTREE_INK_OT_frame_camera,)
