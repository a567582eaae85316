"""Files: EXR and PNG images (images.py), texture images (image_load.py), the files of an animation frame
(frame_files.py) and .blend files read through the add-on's exporter (blend.py)."""
