"""What to install for an OpenCL device that builds our kernels, said for the system the user is on.

PoCL's pip wheels exist for Linux only; on Windows the OpenCL driver comes with the GPU's driver (NVIDIA, AMD,
Intel) or, for the CPU, with Intel's CPU runtime; macOS has Apple's OpenCL framework built in (deprecated by Apple
but still shipped), so there the advice is about the system, not a download.
"""

from __future__ import annotations

import platform as _platform

HINTS = {
    "Windows": ("install or update your graphics driver (NVIDIA, AMD and Intel drivers include OpenCL), or, for "
                "the CPU, Intel's CPU Runtime for OpenCL Applications; on a GPU without an OpenCL driver, "
                "Microsoft's OpenCL and OpenGL Compatibility Pack"),
    "Darwin": ("macOS has OpenCL built in (Apple's OpenCL framework, no install needed): update macOS, and pick "
               "another device under Device if one is listed"),
    "Linux": ("install PoCL, the CPU OpenCL driver (pip install pocl-binary-distribution into this Python, or "
              "apt-get install pocl-opencl-icd), or your GPU's OpenCL driver (NVIDIA's driver, ROCm's "
              "rocm-opencl-runtime, intel-opencl-icd)"),
}


def install_hint(system: str | None = None) -> str:
    """The advice for `system` (platform.system()'s name: Windows, Darwin, Linux; None: this one)."""
    name = _platform.system() if system is None else system
    return HINTS.get(name, "install an OpenCL driver for your GPU or CPU (one the OpenCL ICD loader finds)")
