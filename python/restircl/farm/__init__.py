"""Animations on many machines: frames cut into chunks with warm-up frames (chunks.py), what a worker renders
(worker.py) and the Dask cluster that runs them (cluster.py)."""
