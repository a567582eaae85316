"""Closure kinds: one module per kind of shader node that restircl.Material models (Principled, Diffuse, Glossy),
each with its name, device code, the Material fields it reads and whether it gives a pixel a lobe; registry.py lists
them all. The fields drive the validation (materials/check.py) and the packing into the device Closure record
(upload/materials.py); the device half of a kind is its resolve, opencl/bsdf/closures/<kind>.h, behind the switch
in opencl/bsdf/resolve.h."""
