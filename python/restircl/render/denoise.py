"""Denoising a finished image with Intel Open Image Denoise (the `pyoidn` package), as Cycles does: the colour,
guided by the albedo and shading-normal images of the same pixels (`Settings.denoise`).

Still renders accumulate the guides over their samples (StillAccumulation's aux sums), so that at an edge they mix
the two sides as the colour does; an animation frame uses its own G-buffer's. The image before denoising stays in
the frame as `noisy_image` (the Noisy Image pass). Without pyoidn the image is left as it is, with one warning.
"""

from __future__ import annotations

import warnings

import numpy as np

from .frame import Frame, surface_images

INSTALL_HINT = "pip install pyoidn (or restircl[denoise])"


def available() -> bool:
    try:
        import pyoidn  # noqa: F401
    except Exception:  # an import error, or the library failing to load its shared object
        return False
    return True


def denoise_image(color: np.ndarray, albedo: np.ndarray | None = None, normal: np.ndarray | None = None
                  ) -> np.ndarray:
    """(H, W, 3) float32: `color` (linear HDR, >= 0) denoised by OIDN's RT filter, with the guides if given
    ((H, W, 3): albedo in [0, 1], unit or zero normals). NaN/Inf and negative values are zeroed first: OIDN's
    input must be finite and non-negative, and a NaN would spread over its whole receptive field."""
    import pyoidn

    def clean(a: np.ndarray, lo: float, hi: float) -> np.ndarray:
        a = np.nan_to_num(np.asarray(a, dtype=np.float32)[..., :3], nan=0.0, posinf=0.0, neginf=0.0)
        return np.ascontiguousarray(np.clip(a, lo, hi))

    rgb = clean(color, 0.0, np.finfo(np.float32).max)
    aux_albedo = None if albedo is None else clean(albedo, 0.0, 1.0)
    # OIDN takes the normal only together with the albedo
    aux_normal = None if normal is None or aux_albedo is None else clean(normal, -1.0, 1.0)
    out = pyoidn.denoise(rgb, aux_albedo, aux_normal, hdr=True)
    out = np.asarray(out, dtype=np.float32)
    return np.where(np.isfinite(out), np.maximum(out, 0.0), 0.0).astype(np.float32)


def denoise_frame(frame: Frame, albedo: np.ndarray | None, normal: np.ndarray | None,
                  emission: np.ndarray | None = None) -> bool:
    """Denoise `frame.color` in place (alpha kept), keeping the input as `frame.noisy_image`. The emission the
    camera sees directly (`emission`, (H, W, 3)) is taken out before and added back after: it carries no noise of
    the light estimate, and the denoiser would smear a small bright lamp over its dark neighbours. Returns False,
    with a warning, when pyoidn is missing or fails: the frame is then left as it was."""
    if not available():
        warnings.warn(f"denoise: Intel Open Image Denoise is not installed ({INSTALL_HINT}); the image is not "
                      "denoised", stacklevel=2)
        return False
    em = None if emission is None else np.nan_to_num(np.maximum(np.asarray(emission, np.float32), 0.0))
    try:
        lit = frame.color[..., :3] if em is None else np.maximum(frame.color[..., :3] - em, 0.0)
        clean = denoise_image(lit, albedo, normal)
        if em is not None:
            clean = clean + em
    except Exception as exc:  # a library error must not lose the render
        warnings.warn(f"denoise: Open Image Denoise failed ({type(exc).__name__}: {exc}); the image is not "
                      "denoised", stacklevel=2)
        return False
    frame.noisy_image = frame.color.copy()
    frame.color = frame.color.copy()
    frame.color[..., :3] = clean
    return True


def denoise_by_gbuffer(frame: Frame, g: np.ndarray) -> bool:
    """Denoise an animation frame guided by the albedo and normal of its own G-buffer (`g`, read back), the
    emission the camera sees taken out as in denoise_frame. The TAA output's emission is antialiased over frames,
    this frame's is one jittered sample: at a lamp's edge the difference is clamped at 0 and goes through the
    denoiser."""
    albedo, normal = surface_images(g)
    emission = np.where(np.isfinite(g["emission"][..., :3]), g["emission"][..., :3], 0.0).astype(np.float32)
    return denoise_frame(frame, albedo, normal, emission)
