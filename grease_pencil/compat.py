"""The differences between Blender versions that the Grease Pencil output meets, in one
place.

- 4.5 keeps the (v3) Grease Pencil data in ``bpy.data.grease_pencils_v3``; 5.x renamed
  it to ``bpy.data.grease_pencils``.
- 5.2 places a DOTS material's dots along a stroke's segments (``placement_mode``), and
  a new material's default (RADIUS, one dot per spacing) gives a one-point stroke none:
  stipples drew nothing in the viewport or in a render. COUNT with one dot per stroke
  draws a one-point stroke as a dot (it is what 5.2 makes of a DOTS material saved
  by 5.0). Earlier versions have no placement settings.
"""
import bpy


def grease_pencil_data():
    """The bpy.data collection of (v3) Grease Pencil data-blocks."""
    coll = getattr(bpy.data, "grease_pencils_v3", None)
    if coll is None:
        coll = bpy.data.grease_pencils
    return coll


def stipple_style(gpm):
    """Set a material's Grease Pencil style (MaterialGPencilStyle) to draw one-point
    strokes as dots in this version."""
    gpm.mode = "DOTS"
    if hasattr(gpm, "placement_mode"):
        gpm.placement_mode = "COUNT"
        gpm.placement_count = 1
