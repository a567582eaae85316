"""`restircl bench` and the benchmarks behind docs/benchmarks.md: frame time against the ray floor (main.py),
traversal against Embree (traversal.py, tracers.py), light counts, TAA, the real-time filter, specialised kernels,
the environment's tables and texels, glossy scenes and the per-stage profile of a small frame."""
