"""Polygonisation and the voxel blackboard (pure, numpy only)."""
