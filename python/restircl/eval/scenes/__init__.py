"""Scenes for measuring, kept out of the built-in ones: the tuning kinds of `restircl compare` (held_out.py) and
the scenes where BSDF-sampled candidates matter (bsdf.py)."""
