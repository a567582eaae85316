"""The bounding volume hierarchy: the binned-SAH build (build.py, binning.py), its 4-wide collapse (wide.py) and
the leaf packets the device traverses (packets.py); the traversal is opencl/bvh/."""
