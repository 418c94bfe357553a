"""The typed stub ``_native.pyi`` lists exactly what the compiled module binds.

The stub is written by hand (it carries units and sources the generated one would not); this
test reads the compiled module, so a binding added, renamed or dropped in ``cpp/`` fails here
until the stub says it.
"""

from __future__ import annotations

import ast
import enum
import inspect
from pathlib import Path

from pinwind.dynamics import _native

#: The stub in the source tree: an editable install puts the compiled module elsewhere.
STUB = Path(__file__).resolve().parents[2] / "pinwind" / "dynamics" / "_native.pyi"

#: Names the stub defines for its own annotations, not bound by the module.
TYPE_ALIASES = {"Vector", "Matrix", "Bytes", "Indices"}


def _stub() -> dict[str, set[str]]:
    """Each top-level name of the stub → the public names its class body declares."""
    out: dict[str, set[str]] = {}
    for node in ast.parse(STUB.read_text(encoding="utf-8")).body:
        if isinstance(node, ast.ClassDef):
            members = set()
            for item in node.body:
                if isinstance(item, ast.FunctionDef):
                    members.add(item.name)
                elif isinstance(item, ast.AnnAssign) and isinstance(item.target, ast.Name):
                    members.add(item.target.id)
                elif isinstance(item, ast.Assign):
                    members |= {t.id for t in item.targets if isinstance(t, ast.Name)}
            out[node.name] = {m for m in members if not m.startswith("_")}
        elif isinstance(node, ast.FunctionDef):
            out[node.name] = set()
        elif isinstance(node, ast.Assign):
            out.update({t.id: set() for t in node.targets if isinstance(t, ast.Name)})
    return out


def _bound() -> dict[str, set[str]]:
    """Each public name of the compiled module → the public names of its class, if a class."""
    out: dict[str, set[str]] = {}
    for name, value in vars(_native).items():
        if name.startswith("_"):
            continue
        if isinstance(value, type) and issubclass(value, enum.Enum):
            out[name] = set(value.__members__)
        elif inspect.isclass(value):
            out[name] = {m for m in vars(value) if not m.startswith("_")}
        else:
            out[name] = set()
    return out


def test_the_stub_names_every_binding_of_the_compiled_module_and_no_other():
    stub, bound = _stub(), _bound()
    assert sorted(set(bound) - set(stub)) == []  # bound, not in the stub
    assert sorted(set(stub) - set(bound) - TYPE_ALIASES) == []  # in the stub, not bound


def test_each_class_of_the_stub_has_the_bound_fields_methods_and_members():
    stub, bound = _stub(), _bound()
    for name, members in bound.items():
        if name in stub:
            assert sorted(members ^ stub[name]) == [], name
