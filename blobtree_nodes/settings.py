"""Illustration settings kept on the BlobTree node tree (saved with it)."""
import bpy

PRESETS = {
    # the looks of the papers' figures
    "OUTLINES": dict(grid_resolution=20, agents=32, lod=0.5, hatching=False, stipples=False),
    "STIPPLED": dict(grid_resolution=20, agents=32, lod=0.5, hatching=False, stipples=True),
    "HATCHED": dict(grid_resolution=20, agents=32, lod=0.5, hatching=True, stipples=False),
}


class BlobTreeInkSettings(bpy.types.PropertyGroup):
    grid_resolution: bpy.props.IntProperty(name="Grid", default=20, min=8, max=128,
                                           description="Blackboard grid cells along the longest side")
    agents: bpy.props.IntProperty(name="Agents", default=32, min=1, max=4096,
                                  description="Agents stepped together each system iteration")
    lod: bpy.props.FloatProperty(name="Level of Detail", default=0.5, min=0.0, max=1.0)
    seed: bpy.props.IntProperty(name="Seed", default=0, min=0)
    use_camera: bpy.props.BoolProperty(name="From Camera", default=True,
                                       description="Illustrate for the scene camera (else the viewport's view)")
    hatching: bpy.props.BoolProperty(name="Hatching", default=False)
    stipples: bpy.props.BoolProperty(name="Stipples", default=False)
    region_radius: bpy.props.FloatProperty(name="Region Radius", default=0.5, min=0.001, unit="LENGTH",
                                           description="Radius of the sphere around the 3D cursor that "
                                           "region requests use when no object is selected")


classes = (BlobTreeInkSettings,)
