"""Materials as Blender's shader nodes define them: the closures of a material (material.py), the texture nodes
that feed their inputs (textures.py), their validation (check.py) and their form in the scene file (file.py).
Their device records are packed in upload/."""
