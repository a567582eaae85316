"""The scene model scripts and the add-on fill: a camera, meshes, lights, materials and a world, each validating
itself (camera.py, mesh.py, light.py), the whole (scene.py), its file format (file.py) and re-timing of its
animation (retime.py)."""
