"""restircl: many-light direct lighting (light array, RIS, ReSTIR DI) and TAA in OpenCL C."""

from setuptools import find_packages, setup

setup(
    name="restircl",
    version="0.1.0",
    description="Many-light direct lighting with ReSTIR DI and TAA, in OpenCL C on PoCL or any OpenCL GPU",
    python_requires=">=3.11",
    classifiers=["Programming Language :: Python :: 3.11", "Programming Language :: Python :: 3.13"],
    packages=[*find_packages(where="python", include=["restircl", "restircl.*"]), "restircl.opencl"],
    package_dir={"": "python", "restircl.opencl": "opencl"},
    # every OpenCL source, at any depth; the precomputed GGX tables (tools/ship_tables.py)
    package_data={"restircl.opencl": ["**/*.h", "**/*.cl"], "restircl.upload": ["ggx_tables.npz", "glass_tables.npz"]},
    install_requires=["numpy>=1.24", "pyopencl>=2024.1", "openexr>=3.3", "pillow>=10"],
    extras_require={
        # PoCL's wheels exist for Linux only: elsewhere the extra adds nothing and the system's OpenCL is used
        "pocl": ['pyopencl[pocl]>=2024.1; sys_platform == "linux"'],
        # libclang: the OpenCL C front end for NVIDIA, AMD and SPIR targets (tests/test_portability.py)
        # distributed: the farm's engine (restircl render --workers/--scheduler, docs/farm.md; pure Python)
        # flip-evaluator: the FLIP columns of restircl report and eval/report/denoise.py (empty, with a note, without)
        "test": ["pytest>=8", "pytest-xdist>=3", "ruff>=0.5", "scipy>=1.10", "matplotlib>=3.7", "libclang>=16", "distributed>=2024.8",
                 "pyoidn>=2.5", "flip-evaluator>=1.7"],
        "farm": ["distributed>=2024.8"],
        "denoise": ["pyoidn>=2.5"],  # Intel Open Image Denoise (Settings.denoise)
        "bench": ["embreex>=4.3", "matplotlib>=3.7", "flip-evaluator>=1.7"],
        # bpy is Blender as a module, one Python per release line: 4.2 LTS-5.0 use CPython 3.11, 5.1 and newer 3.13
        # (docs/blender.md, "Supported releases"); each bpy pins the numpy its Blender ships (5.0.1: < 2).
        "blender": ['bpy==5.0.1; python_version == "3.11"', 'bpy==5.3.0; python_version == "3.13"'],
        "blender-lts": ['bpy==4.2.23; python_version == "3.11"'],
    },
    entry_points={"console_scripts": ["restircl=restircl.cli.main:main"]},
)
