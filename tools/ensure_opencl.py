"""Make sure an OpenCL device here can build restircl's kernels; on Debian/Ubuntu, install the system PoCL if not.

The PoCL inside the pyopencl wheel (LLVM 14) cannot build for CPUs newer than its LLVM (AMD Zen 5 and later: "unknown
target CPU 'generic'"). Debian's `pocl-opencl-icd` (PoCL 3.1 in Debian 12) picks its code target per CPU feature
set and works there; restircl's device choice then takes whichever device builds (python/restircl/core/device.py).

Exit status 0 when a device builds (after installing, where that was needed and allowed), 1 otherwise, with what to
run. Installs only as root or with password-less sudo, and only with apt-get; `--dry-run` says what it would do.
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys

PACKAGE = "pocl-opencl-icd"


def device_problem() -> str | None:
    """None if the default choice finds a device that builds, else the reason (in a fresh process, so that a driver
    installed a moment ago is seen)."""
    code = (
        "import sys, warnings\n"
        "warnings.simplefilter('ignore')\n"
        "from restircl.core.device import choose_device, DeviceError\n"
        "try:\n"
        "    print(choose_device()[0].label)\n"
        "except DeviceError as e:\n"
        "    print(e); sys.exit(1)\n"
    )
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    return None if run.returncode == 0 else (run.stdout + run.stderr).strip()


def install_command() -> list[str] | None:
    """The apt-get command that may run here without a password, or None."""
    if shutil.which("apt-get") is None:
        return None
    apt = ["apt-get", "install", "-y", "-q", PACKAGE]
    if os.geteuid() == 0:
        return apt
    if shutil.which("sudo") and subprocess.run(["sudo", "-n", "true"], capture_output=True).returncode == 0:
        return ["sudo", "-n", *apt]
    return None


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--dry-run", action="store_true", help="say what would be installed, install nothing")
    a = ap.parse_args(argv)
    problem = device_problem()
    if problem is None:
        print("OpenCL: a device builds restircl's kernels")
        return 0
    print(f"OpenCL: {problem}")
    cmd = install_command()
    if cmd is None:
        print(f"install a system PoCL, e.g. `sudo apt-get install {PACKAGE}`, or another OpenCL driver for this "
              "machine, then run this again")
        return 1
    print("installing:", " ".join(cmd))
    if a.dry_run:
        return 1
    env = dict(os.environ, DEBIAN_FRONTEND="noninteractive")
    if subprocess.run(cmd, env=env, stdin=subprocess.DEVNULL).returncode != 0:
        print(f"`{' '.join(cmd)}` failed")
        return 1
    problem = device_problem()
    if problem is not None:
        print(f"OpenCL, after installing {PACKAGE}: {problem}")
        return 1
    print(f"OpenCL: {PACKAGE} installed; a device builds restircl's kernels")
    return 0


if __name__ == "__main__":
    sys.exit(main())
