"""Cycles beside restircl: the bridge that writes our scenes into bpy and renders them (bridge.py, materials.py,
world.py), `restircl compare` (compare.py, compare_report.py) and the still-estimator measurement
(still_candidates.py)."""
