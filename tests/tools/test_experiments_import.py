"""Every probe under tools/experiments imports: a module that imports a name another change removed (as
fill_bias.py did restir_motion's add_defines) fails here rather than when someone reruns a documented command."""

from __future__ import annotations

import importlib
import pkgutil

import pytest

import tools.experiments as experiments

MODULES = sorted(m.name for m in pkgutil.iter_modules(experiments.__path__))


def test_the_probes_are_found() -> None:
    assert len(MODULES) > 50 and "restir_motion" in MODULES and "fill_bias" in MODULES


@pytest.mark.parametrize("name", MODULES)
def test_probe_imports(name: str) -> None:
    module = importlib.import_module(f"tools.experiments.{name}")
    assert module.__doc__, f"tools/experiments/{name}.py says what it measures in its docstring"
