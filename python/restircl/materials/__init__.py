"""Materials on the host: the model as Blender's shader nodes define it (material.py), the texture nodes that feed
its inputs (textures.py), one module per closure kind with their registry (closures/), validation (check.py) and
the scene file's form (file.py). Their device records are packed in upload/."""
