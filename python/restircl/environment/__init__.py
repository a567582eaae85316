"""The world light on the host: the model (world.py: a colour or an image times a strength), its texels (image.py,
pack.py), its importance-sampling tables (table.py), the sun test (sun.py) and its form in the scene file (file.py).
Its light record is lights/environment.py."""
