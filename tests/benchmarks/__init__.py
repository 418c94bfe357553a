"""Tests of the benchmarks' own modules, loaded from their files (benchmarks/ is no package)."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path
from types import ModuleType


def benchmark_module(file_name: str, module_name: str) -> ModuleType:
    """The module of ``benchmarks/<file_name>``, registered as ``module_name`` (dataclasses look
    their module up in ``sys.modules``)."""
    path = Path(__file__).resolve().parents[2] / "benchmarks" / file_name
    spec = importlib.util.spec_from_file_location(module_name, path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module
