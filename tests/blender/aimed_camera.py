"""A scene camera for the Blender tier's tests: made, made the scene's and aimed."""
import bpy
from mathutils import Vector


def aimed_camera(location, target):
    """A new camera at ``location`` looking at ``target``, the scene's camera."""
    sc = bpy.context.scene
    cam = bpy.data.objects.new("Cam", bpy.data.cameras.new("Cam"))
    sc.collection.objects.link(cam)
    sc.camera = cam
    cam.location = location
    cam.rotation_euler = (Vector(target) - cam.location).to_track_quat("-Z", "Y").to_euler()
    bpy.context.view_layer.update()
    return cam
