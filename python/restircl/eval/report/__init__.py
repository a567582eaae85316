"""`restircl report`: error against run time for a still camera (main.py) and per frame for a moving one
(moving.py), the methods (methods.py), cached references (reference.py), the files (files.py), the flicker metric
(flicker.py), the denoiser's worth (denoise.py) and the viewport policy along an orbit (viewport_orbit.py)."""
