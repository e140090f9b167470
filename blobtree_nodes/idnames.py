"""The Blender type name of a BlobTree node tree, named once for every module that asks
whether a node group is one."""
TREE = "BlobTreeInkNodeTree"
