"""The scene as the device holds it: the device scene that uploads what changed (device_scene.py), and the packing
of materials, textures, per-triangle attributes and constant tables (materials.py, textures.py,
tri_attributes.py, ggx_tables.py), and the codes and constants of the host/device line (codes.py, which
generates opencl/codes.h)."""
