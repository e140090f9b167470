"""The one Grease Pencil API difference between Blender 4.5 LTS and 5.x, in one place.

4.5 keeps the new (v3) Grease Pencil data in ``bpy.data.grease_pencils_v3``; 5.x
renamed it to ``bpy.data.grease_pencils``.
"""
import bpy


def grease_pencil_data():
    """The bpy.data collection of (v3) Grease Pencil data-blocks."""
    coll = getattr(bpy.data, "grease_pencils_v3", None)
    if coll is None:
        coll = bpy.data.grease_pencils
    return coll
