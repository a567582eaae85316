"""Rendering frames on the device: the pipeline (pipeline.py, Renderer: a frame's stages in order), the frame's policy
(plan.py: what a frame runs and reuses, a pure function of the settings and the frame's situation), the stages
(stages.py), the history they ping-pong (history.py), the rendered frame and its read-back (frame.py), its passes
(passes.py), still renders (still.py: accumulation, half buffers, error estimate; still_method.py: their
estimator), the Sobol sampler (qmc.py), the camera records and jitter (camera.py), the compiled features
(features.py) and denoising (denoise.py)."""
