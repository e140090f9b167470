"""The command line's scene: a camera at the eye looking at the model, a sun towards the
light, white paper (Workbench), all reused when they exist."""
import bpy
import numpy as np

from ..pipeline.framing import LENS, SENSOR

CAMERA, LIGHT = "BlobTree Ink Camera", "BlobTree Ink Light"


def setup(scene, centre, eye, size=1024, light_dir=(0.4, -0.6, 0.7)):
    cam = bpy.data.objects.get(CAMERA)
    if cam is None:
        cam = bpy.data.objects.new(CAMERA, bpy.data.cameras.new(CAMERA))
        scene.collection.objects.link(cam)
    cam.data.lens = LENS
    cam.data.sensor_width = SENSOR
    cam.location = tuple(float(x) for x in eye)
    look = np.asarray(centre, float) - np.asarray(eye, float)
    cam.rotation_euler = _look_rotation(look)
    cam.data.clip_end = max(1000.0, 10 * float(np.linalg.norm(look)))
    scene.camera = cam
    light = bpy.data.objects.get(LIGHT)
    if light is None:
        light = bpy.data.objects.new(LIGHT, bpy.data.lights.new(LIGHT, "SUN"))
        scene.collection.objects.link(light)
    light.rotation_euler = _look_rotation(-np.asarray(light_dir, float))
    r = scene.render
    r.engine = "BLENDER_WORKBENCH"
    r.resolution_x = r.resolution_y = int(size)
    r.resolution_percentage = 100
    r.film_transparent = False
    r.image_settings.file_format = "PNG"
    if scene.world is None:
        scene.world = bpy.data.worlds.new("BlobTree Ink Paper")
    scene.world.color = (1.0, 1.0, 1.0)            # Workbench renders the world colour: paper
    scene.view_settings.view_transform = "Standard"
    bpy.context.view_layer.update()              # the objects' world matrices, read by the job
    return cam, light


def _look_rotation(direction):
    """Euler angles pointing an object's -Z along direction with +Y up."""
    from mathutils import Vector
    return Vector(tuple(float(x) for x in direction)).to_track_quat("-Z", "Y").to_euler()
