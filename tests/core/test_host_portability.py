"""The add-on and the core run on Windows and macOS too: a scan of their Python (the syntax tree of every module of
addon/restircl_blender and python/restircl, less eval/, the measuring tools the core never imports) for what only
Linux or only PoCL has: fork, signals, POSIX-only modules, shell commands, fixed Unix paths, paths joined with "/",
PoCL's environment, include paths among the build options (a Windows or macOS install path has spaces, which
drivers split options at) and build options that are not OpenCL 1.2's."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SCANNED = (ROOT / "addon" / "restircl_blender", ROOT / "python" / "restircl")
SKIPPED = (ROOT / "python" / "restircl" / "eval",)

POSIX_MODULES = {"signal", "fcntl", "termios", "pwd", "grp", "resource", "posix", "pty", "tty", "crypt", "syslog"}
POSIX_CALLS = {"fork", "forkpty", "setsid", "setpgrp", "killpg", "getuid", "geteuid", "getgid", "getpgid", "nice",
               "sync", "chown", "mkfifo", "system", "popen", "getloadavg", "sched_setaffinity"}
UNIX_PATHS = ("/tmp", "/dev/", "/usr/", "/proc/", "/etc/", "/var/", "/home/", "/opt/")
# The program build options of the OpenCL 1.2 specification (section 5.6.4): what every vendor's compiler takes.
# Hits that are not paths, each with the line's text that makes it one.
NOT_PATHS = {"python/restircl/cli/main.py": "'/'.join(flag_of(Settings, n)"}  # option names in an argparse message
CL12_OPTIONS = {"-cl-std=CL1.1", "-cl-std=CL1.2", "-cl-denorms-are-zero", "-cl-single-precision-constant",
                "-cl-opt-disable", "-cl-mad-enable", "-cl-no-signed-zeros", "-cl-unsafe-math-optimizations",
                "-cl-finite-math-only", "-cl-fast-relaxed-math", "-cl-kernel-arg-info", "-w", "-Werror"}


def scan(source: str, name: str = "<string>") -> list[str]:
    """What in `source` would not run, or not the same, on Windows or macOS, or without PoCL: 'name:line: why'."""
    found: list[str] = []

    def flag(node: ast.AST, why: str) -> None:
        found.append(f"{name}:{getattr(node, 'lineno', 0)}: {why}")

    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import | ast.ImportFrom):
            mods = [a.name for a in node.names] if isinstance(node, ast.Import) else [node.module or ""]
            for mod in mods:
                if mod.split(".")[0] in POSIX_MODULES:
                    flag(node, f"imports {mod} (POSIX only)")
        elif isinstance(node, ast.Call):
            func = node.func
            attr = func.attr if isinstance(func, ast.Attribute) else getattr(func, "id", "")
            owner = func.value.id if isinstance(func, ast.Attribute) and isinstance(func.value, ast.Name) else ""
            if owner == "os" and attr in POSIX_CALLS:
                flag(node, f"os.{attr} (POSIX only, or a shell)")
            if any(k.arg == "shell" and not (isinstance(k.value, ast.Constant) and k.value.value is False)
                   for k in node.keywords):
                flag(node, "a shell command (shell=True)")
            if attr in ("get_context", "set_start_method") and any(
                    isinstance(a, ast.Constant) and a.value in ("fork", "forkserver") for a in node.args):
                flag(node, "multiprocessing by fork (no fork on Windows, unsafe on macOS)")
            if attr == "join" and isinstance(func, ast.Attribute) and isinstance(func.value, ast.Constant) \
                    and func.value.value == "/":
                flag(node, 'a path joined with "/".join (use pathlib or os.path.join)')
        elif isinstance(node, ast.BinOp) and isinstance(node.op, ast.Add):
            for side in (node.left, node.right):
                if isinstance(side, ast.Constant) and isinstance(side.value, str) and side.value != "/" and (
                        side.value.startswith("/") or side.value.endswith("/")) and " " not in side.value:
                    flag(node, f'a path joined with + "{side.value}" (use pathlib or os.path.join)')
        elif isinstance(node, ast.Subscript) and isinstance(node.ctx, ast.Store):
            key = node.slice
            if isinstance(key, ast.Constant) and isinstance(key.value, str) and key.value.startswith("POCL_"):
                flag(node, f"sets {key.value} (PoCL only)")
        if isinstance(node, ast.JoinedStr) and node.values and isinstance(node.values[0], ast.Constant) \
                and str(node.values[0].value).startswith("-I"):
            flag(node, "an include path as a build option (drivers split options at the spaces of a path)")
        if isinstance(node, ast.Constant) and isinstance(node.value, str):
            text = node.value
            if text.startswith(UNIX_PATHS) and "\n" not in text:
                flag(node, f"the Unix path {text!r}")
            if text.startswith("-cl-") and text not in CL12_OPTIONS:
                flag(node, f"the build option {text!r} is not OpenCL 1.2's")
            if "Portable Computing Language" in text:
                flag(node, "a choice by PoCL's platform name")
    return found


def _modules() -> list[Path]:
    return sorted(p for base in SCANNED for p in base.rglob("*.py")
                  if "__pycache__" not in p.parts and not any(p.is_relative_to(s) for s in SKIPPED))


def test_addon_and_core_have_nothing_only_linux_or_pocl_has():
    modules = _modules()
    assert len(modules) > 100 and ROOT / "addon" / "restircl_blender" / "engine.py" in modules
    found = []
    for path in modules:
        rel, text = path.relative_to(ROOT).as_posix(), path.read_text()
        lines = text.splitlines()
        found += [hit for hit in scan(text, rel)
                  if not (rel in NOT_PATHS and NOT_PATHS[rel] in lines[int(hit.split(":")[1]) - 1])]
    assert not found, "\n".join(found)


@pytest.mark.parametrize(("snippet", "why"), [
    ("import os\nos.fork()", "os.fork"),
    ("import signal\nsignal.signal(signal.SIGTERM, None)", "imports signal"),
    ("from fcntl import flock", "imports fcntl"),
    ("import os\nos.system('ls')", "os.system"),
    ("import subprocess\nsubprocess.run('ls -l', shell=True)", "shell=True"),
    ("cache = '/tmp/restircl'", "Unix path '/tmp/restircl'"),
    ("p = folder + '/kernels'", 'joined with + "/kernels"'),
    ("p = '/'.join([a, b])", '"/".join'),
    ("import multiprocessing\nmultiprocessing.get_context('fork')", "by fork"),
    ("import os\nos.environ['POCL_CACHE_DIR'] = d", "sets POCL_CACHE_DIR"),
    ("opts = ['-cl-std=CL1.2', '-cl-pocl-fast']", "'-cl-pocl-fast' is not OpenCL 1.2's"),
    ("use = p.name == 'Portable Computing Language'", "PoCL's platform name"),
    ("opts = [f'-I{src_dir}', '-cl-std=CL1.2']", "an include path as a build option"),
])
def test_the_scan_finds_each_kind(snippet, why):
    found = scan(snippet, "x.py")
    assert len(found) == 1 and why in found[0], found


def test_the_scan_passes_what_runs_everywhere():
    ok = ("import os, subprocess, tempfile\nfrom pathlib import Path\n"
          "p = Path(tempfile.gettempdir()) / 'restircl' / 'cache'\nq = os.path.join(d, 'kernels')\n"
          "subprocess.run([sys.executable, '-c', 'pass'], shell=False)\nmsg = f'{done}/{total}'\n"
          "opts = ['-cl-std=CL1.2', '-cl-denorms-are-zero']\nflag = '--wheel-dir'\n")
    assert scan(ok) == []
