"""Names a package exports, imported when first used (PEP 562 module ``__getattr__``).

``import pinwind`` then costs next to nothing, and a command imports only what it uses: ``pinwind
modes`` never loads the log reader or the simulation loop, ``pinwind --version`` not even numpy.
A package writes its exports as ordinary imports under ``if TYPE_CHECKING:``, which mypy and IDEs
read, and ``lazy_exports`` reads the same block (as scientific-python's ``lazy_loader`` reads a
package's ``.pyi`` stub): the first access to a name imports its module and keeps the value in the
package, so later accesses are plain attribute reads. A submodule is an attribute too, imported
on first use (``import pinwind`` once imported every subpackage: ``pinwind.analysis.load_sharing``
after ``import pinwind`` keeps working).

Some exports share their name with the submodule that defines them (``pinwind.dynamics.simulate``
the function in ``pinwind/dynamics/simulate.py``, ``pinwind.gears.involute``). The import system
binds a submodule on its package once it has run, which would put the module where the function
was; the package's module class (``LazyPackage``) binds the function instead, as the eager
``from pinwind.dynamics.simulate import simulate`` of the package did. A submodule named like an
export it does not define (``pinwind.cli.app``, the module that creates the application
``pinwind.cli.app``) is not bound at all.
"""

from __future__ import annotations

import ast
import importlib
import importlib.util
import sys
from collections.abc import Callable
from pathlib import Path
from types import ModuleType
from typing import Any


def type_checking_imports(source: str) -> dict[str, tuple[str, str]]:
    """Each name imported under a top-level ``if TYPE_CHECKING:`` → (module, name in module)."""
    found: dict[str, tuple[str, str]] = {}
    for node in ast.parse(source).body:
        if not (isinstance(node, ast.If) and isinstance(node.test, ast.Name)):
            continue
        if node.test.id != "TYPE_CHECKING":
            continue
        for statement in node.body:
            if isinstance(statement, ast.ImportFrom) and statement.module and not statement.level:
                for alias in statement.names:
                    found[alias.asname or alias.name] = (statement.module, alias.name)
    return found


class LazyPackage(ModuleType):
    """A package whose exports stay bound when a submodule of the same name is imported."""

    _lazy_sources: dict[str, tuple[str, str]]

    def __setattr__(self, name: str, value: Any) -> None:
        """Bind ``value``; a submodule never replaces the export of its name.

        The submodule that defines the export ``name`` binds that export; another submodule of
        that name is not bound (``pinwind.cli.app`` the module, beside the export ``app`` that
        ``cli/verbs.py`` completes with every verb), and the export is imported on first use.
        """
        source = self.__dict__.get("_lazy_sources", {}).get(name)
        if isinstance(value, ModuleType) and source:
            if value.__name__ != source[0]:
                return
            value = getattr(value, source[1])
        super().__setattr__(name, value)


def lazy_exports(package: str) -> tuple[Callable[[str], Any], Callable[[], list[str]]]:
    """The ``__getattr__`` and ``__dir__`` of a package whose exports are imported on first use.

    Also makes the package a ``LazyPackage``, so that a submodule named like one of its exports
    does not replace that export.

    Args:
        package: the package's ``__name__``, called from its ``__init__``, whose names under
            ``if TYPE_CHECKING:`` become its lazy exports.
    """
    module = sys.modules[package]
    namespace = module.__dict__
    sources = type_checking_imports(Path(namespace["__file__"]).read_text(encoding="utf-8"))
    namespace["_lazy_sources"] = sources
    module.__class__ = LazyPackage

    def __getattr__(name: str) -> Any:
        if name in sources:
            source, original = sources[name]
            value = getattr(importlib.import_module(source), original)
            namespace[name] = value
            return value
        if name.isidentifier() and importlib.util.find_spec(f"{package}.{name}") is not None:
            return importlib.import_module(f"{package}.{name}")  # which binds it on the package
        raise AttributeError(f"module {package!r} has no attribute {name!r}")

    def __dir__() -> list[str]:
        return sorted({*namespace, *sources})

    return __getattr__, __dir__
