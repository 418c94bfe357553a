"""Lazy exports: ``import pinwind`` and the command line load no heavy library they do not use.

Each check runs a fresh interpreter (``sys.executable``, the caller's ``PYTHONPATH``) and reads its
``sys.modules``: what a module imports is a fact of the code, not of timing, so these hold on a
loaded machine too (``benchmarks/modes.py`` measures the time).
"""

from __future__ import annotations

import importlib
import json
import subprocess
import sys
from pathlib import Path
from types import ModuleType

import pytest

from pinwind.lazy_exports import type_checking_imports
from tests.conftest import MODELS

#: Libraries that only logs, plots, replays, exports and fatigue sets need.
HEAVY = ("matplotlib", "rerun", "mcap", "pyarrow", "dask", "pandas", "scipy")
#: Packages whose exports are imported on first use (``lazy_exports.py``).
LAZY_PACKAGES = (
    "pinwind",
    "pinwind.analysis",
    "pinwind.dynamics",
    "pinwind.gears",
    "pinwind.io",
    "pinwind.loads",
    "pinwind.modes",
    "pinwind.runs",
    "pinwind.testing",
)


def loaded_after(code: str) -> set[str]:
    """Top-level packages and pinwind modules in ``sys.modules`` after running ``code``."""
    report = (
        "import json, sys\n"
        "names = {m.split('.')[0] for m in sys.modules} | {m for m in sys.modules "
        "if m.startswith('pinwind.')}\n"
        "print(json.dumps(sorted(names)))\n"
    )
    out = subprocess.run(
        [sys.executable, "-c", code + "\n" + report],
        capture_output=True,
        text=True,
        timeout=300,
        check=True,
    )
    return set(json.loads(out.stdout.splitlines()[-1]))


def test_import_pinwind_loads_no_numerical_or_log_library():
    loaded = loaded_after("import pinwind")
    assert loaded & {*HEAVY, "numpy", "pinocchio", "proxsuite"} == set()
    assert {m for m in loaded if m.startswith("pinwind.")} == {"pinwind.lazy_exports"}


def test_the_command_line_app_loads_neither_numpy_nor_pinocchio():
    # ``pinwind --version`` and ``--help`` import every verb module: each imports its heavy
    # modules inside its command.
    loaded = loaded_after("import pinwind.cli")
    assert loaded & {*HEAVY, "numpy", "pinocchio", "proxsuite"} == set()


def loaded_by_pinwind_modes() -> set[str]:
    """The modules a child process holds after ``pinwind modes`` on the CART 600 model."""
    model = str(MODELS / "cart600_gearbox.urdf")
    return loaded_after(
        "import sys\n"
        "from pinwind.cli import main\n"
        f"sys.argv = ['pinwind', 'modes', {model!r}]\n"
        "try:\n    main()\nexcept SystemExit as end:\n    assert not end.code, end.code\n"
    )


def test_pinwind_modes_loads_no_log_plot_or_solver_library():
    # The whole command, run in the child: the model, the linearisation and the table.
    loaded = loaded_by_pinwind_modes()
    assert "pinwind.modes.linearisation" in loaded  # the command did run
    assert loaded & {*HEAVY, "proxsuite"} == set()
    assert {m for m in loaded if m.startswith(("pinwind.io", "pinwind.dynamics.simulate"))} == set()


def test_pinwind_modes_imports_neither_pydantic_nor_the_other_verbs():
    # Issue 24 (``pinwind modes`` < 1 s): typer converts values through pydantic, which
    # ``cli/conversions.py`` spares plain values; the other verbs' modules are neither imported
    # nor built into commands (``VERB_MODULES``).
    from pinwind.cli import VERB_MODULES

    loaded = loaded_by_pinwind_modes()
    assert "pinwind.modes.linearisation" in loaded  # the command did run
    assert loaded & {"pydantic", "pydantic_core", "annotated_types", "typing_inspection"} == set()
    others = {f"pinwind.cli.{module}" for module in VERB_MODULES.values()} - {"pinwind.cli.modes"}
    assert others, VERB_MODULES
    assert loaded & others == set()
    assert {m for m in loaded if m.startswith(("pinwind.loads", "pinwind.cli.verbs"))} == set()


def test_the_app_module_does_not_replace_the_app_with_every_verb():
    # ``pinwind.cli.app`` is both the module that creates the application and the application
    # with every verb (``cli/verbs.py``): a command that imported the module alone leaves it so.
    loaded_after(
        "import sys\n"
        "import typer, typer.main\n"
        "from pinwind.cli import main\n"
        "sys.argv = ['pinwind', '--version']\n"
        "try:\n    main()\nexcept SystemExit as end:\n    assert not end.code, end.code\n"
        "assert 'pinwind.cli.app' in sys.modules and 'pinwind.cli.verbs' not in sys.modules\n"
        "from pinwind.cli import app\n"
        "assert isinstance(app, typer.Typer), app\n"
        "assert {'modes', 'simulate', 'sweep'} <= set(typer.main.get_command(app).commands)\n"
    )


def test_an_export_named_like_its_submodule_stays_the_export():
    # The import system binds a submodule on its package once it has run; the eager
    # ``from pinwind.dynamics.simulate import simulate`` bound the function over it.
    loaded_after(
        "import sys\n"
        "import pinwind.analysis.load_sharing, pinwind.dynamics.simulate, pinwind.gears.involute\n"
        "import pinwind.gears.mesh_stiffness\n"
        "from types import FunctionType\n"
        "from pinwind.analysis import load_sharing\n"
        "from pinwind.dynamics import simulate\n"
        "from pinwind.gears import involute, mesh_stiffness\n"
        "for f in (load_sharing, simulate, involute, mesh_stiffness):\n"
        "    assert isinstance(f, FunctionType), f\n"
        "assert sys.modules['pinwind.dynamics.simulate'].simulate is simulate\n"
    )


def test_subpackages_are_attributes_of_pinwind_after_import_pinwind_alone():
    # The tutorial's ``pinwind.analysis.load_sharing(res, gb)``: the eager ``import pinwind``
    # imported every subpackage, the lazy one imports them on first access.
    loaded_after(
        "import pinwind\n"
        "from types import FunctionType, ModuleType\n"
        "assert isinstance(pinwind.analysis.load_sharing, FunctionType)\n"
        "assert isinstance(pinwind.dynamics.series, ModuleType)\n"
        "assert pinwind.units.RAD_S_PER_RPM > 0\n"
        "assert not hasattr(pinwind, 'analysis.load_sharing')\n"
    )


@pytest.mark.parametrize("name", LAZY_PACKAGES)
def test_every_exported_name_is_declared_and_resolves(name: str):
    package = importlib.import_module(name)
    assert package.__file__ is not None
    declared = type_checking_imports(Path(package.__file__).read_text(encoding="utf-8"))
    assert set(package.__all__) - {"__version__"} == set(declared)
    assert set(package.__all__) <= set(dir(package))
    for export, (module, original) in declared.items():
        value = getattr(package, export)
        assert value is getattr(importlib.import_module(module), original)
        assert not isinstance(value, ModuleType)


def test_an_unknown_name_raises_attribute_error_naming_the_package():
    import pinwind

    with pytest.raises(AttributeError, match="'pinwind' has no attribute 'lod'"):
        pinwind.lod  # noqa: B018
    assert not hasattr(pinwind, "lod")


def test_type_checking_imports_reads_only_the_type_checking_block():
    source = (
        "from typing import TYPE_CHECKING\n"
        "from a.eager import e\n"
        "if TYPE_CHECKING:\n"
        "    from a.b import x, y as z\n"
        "    import a.c\n"
        "if other:\n"
        "    from a.d import w\n"
    )
    assert type_checking_imports(source) == {"x": ("a.b", "x"), "z": ("a.b", "y")}
