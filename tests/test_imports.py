"""The modules of pinwind import each other without a cycle, and its packages without a loop.

The graph is read statically with ``ast``: every ``import`` and ``from ... import`` counts, also
inside functions and under ``TYPE_CHECKING`` (a cycle hidden in a function is still a cycle of
concepts), relative imports are resolved, and importing a submodule also imports its parent
packages' ``__init__``. A module always runs after its own parent packages started, so the implied
edge from a module to its own parents is not a dependency; an explicit import of a parent (to take
a name from its ``__init__``) is.
"""

from __future__ import annotations

import ast
from pathlib import Path

#: The pinwind package folder, read as files (nothing of it is imported).
PINWIND = Path(__file__).resolve().parents[1] / "pinwind"

#: Imports (module, imported module) left out of the check until their cycle is fixed, each with
#: who fixes it; the packages they would also import are left out with them.
KNOWN_EDGES: set[tuple[str, str]] = set()


def package_modules(root: Path, package: str) -> dict[str, Path]:
    """Dotted name of every module (``.py``, and ``.pyi`` of a compiled one) under ``root``."""
    modules: dict[str, Path] = {}
    for path in sorted(root.rglob("*.py*")):
        if path.suffix not in (".py", ".pyi") or "__pycache__" in path.parts:
            continue
        parts = [package, *path.relative_to(root).with_suffix("").parts]
        if parts[-1] == "__init__":
            parts.pop()
        name = ".".join(parts)
        if path.suffix == ".py" or name not in modules:
            modules[name] = path
    return modules


def _parents(name: str) -> list[str]:
    """The packages that hold module ``name``, outermost first (without ``name``)."""
    parts = name.split(".")
    return [".".join(parts[:i]) for i in range(1, len(parts))]


def _imported(
    node: ast.Import | ast.ImportFrom, module: str, is_package: bool, modules: dict[str, Path]
) -> list[str]:
    """Modules an import statement in ``module`` names, without their implied parents."""
    if isinstance(node, ast.Import):
        return [alias.name for alias in node.names]
    base = node.module or ""
    if node.level:
        # Level 1 is the package itself in an ``__init__``, the enclosing package elsewhere.
        anchor = module.split(".")
        anchor = anchor[: len(anchor) - node.level + (1 if is_package else 0)]
        base = ".".join([*anchor, base] if base else anchor)
    submodules = [f"{base}.{alias.name}" for alias in node.names]
    if all(name in modules for name in submodules):
        return submodules  # ``from package import module``: the package is only a parent
    return [base, *submodules]  # a name defined in ``base`` itself


def import_graph(
    root: Path, package: str, *, known: set[tuple[str, str]] | None = None
) -> dict[str, set[str]]:
    """Module → the package's modules it imports (directly, or as a parent package).

    ``known``: imports (module, imported module) to leave out, with the parents they imply.
    """
    known = known or set()
    modules = package_modules(root, package)
    graph: dict[str, set[str]] = {}
    for module, path in modules.items():
        if path.suffix == ".pyi":
            graph[module] = set()
            continue
        is_package = path.name == "__init__.py"
        own_parents = set(_parents(module))
        targets: set[str] = set()
        for node in ast.walk(ast.parse(path.read_text(), filename=str(path))):
            if not isinstance(node, ast.Import | ast.ImportFrom):
                continue
            for name in _imported(node, module, is_package, modules):
                if name not in modules:
                    continue  # another library, or a name (not a module) inside a module
                if (module, name) in known:
                    continue
                targets.add(name)
                targets.update(set(_parents(name)) - own_parents)
        targets.discard(module)
        graph[module] = targets
    return graph


def package_graph(graph: dict[str, set[str]], package: str) -> dict[str, set[str]]:
    """Each subpackage or top-level module of ``package`` → those its modules import.

    ``pinwind.io.log_reader`` counts as ``pinwind.io``, ``pinwind.units`` as itself; the
    package's own ``__init__`` (the top-level exports) is left out.
    """
    depth = package.count(".") + 2

    def unit(name: str) -> str:
        return ".".join(name.split(".")[:depth])

    out: dict[str, set[str]] = {}
    for module, targets in graph.items():
        if module == package:
            continue
        imported = {unit(t) for t in targets if t != package} - {unit(module)}
        out.setdefault(unit(module), set()).update(imported)
    return out


def find_cycle(graph: dict[str, set[str]]) -> list[str] | None:
    """One cycle of the graph as ``[a, b, ..., a]``, or None when it has none."""
    state: dict[str, int] = {}  # 1 on the current path, 2 done
    path: list[str] = []

    def visit(node: str) -> list[str] | None:
        state[node] = 1
        path.append(node)
        for target in sorted(graph.get(node, ())):
            if state.get(target) == 1:
                return [*path[path.index(target) :], target]
            if target not in state:
                cycle = visit(target)
                if cycle is not None:
                    return cycle
        path.pop()
        state[node] = 2
        return None

    for node in sorted(graph):
        if node not in state:
            cycle = visit(node)
            if cycle is not None:
                return cycle
    return None


def test_pinwind_modules_import_without_a_cycle() -> None:
    graph = import_graph(PINWIND, "pinwind", known=KNOWN_EDGES)
    assert "pinwind.dynamics.stepper" in graph  # the walk found the package
    cycle = find_cycle(graph)
    assert cycle is None, "import cycle: " + " -> ".join(cycle or [])


def test_pinwind_packages_import_without_a_loop() -> None:
    # A loop of packages whose modules form no cycle (a imports b.x, b.y imports a.z) is still
    # two layers that each need the other (issue 37).
    graph = package_graph(import_graph(PINWIND, "pinwind"), "pinwind")
    assert {"pinwind.dynamics", "pinwind.modes"} <= graph["pinwind.cli"]  # the walk found them
    cycle = find_cycle(graph)
    assert cycle is None, "package loop: " + " -> ".join(cycle or [])


def test_analysis_imports_no_logs_scenarios_runs_or_fatigue() -> None:
    # analysis/ is computation on Results and arrays: reading logs is io's, running scenarios,
    # sweeps and fatigue sets is runs', and life/ sits above it (issue 37 item 1).
    graph = package_graph(import_graph(PINWIND, "pinwind"), "pinwind")
    assert "pinwind.dynamics" in graph["pinwind.analysis"]  # the walk found its imports
    above = {"pinwind.io", "pinwind.runs", "pinwind.life"}
    assert graph["pinwind.analysis"] & above == set()


def test_life_reads_no_scenario_and_runs_no_case() -> None:
    # A fatigue set's file and its cases' runs are runs/fatigue_set_file.py and
    # runs/case_runner.py; life/ computes on the histories they give it.
    graph = package_graph(import_graph(PINWIND, "pinwind"), "pinwind")
    assert "pinwind.analysis" in graph["pinwind.life"]
    assert "pinwind.runs" not in graph["pinwind.life"]


def test_only_the_checks_and_the_command_line_import_the_runs() -> None:
    # runs/ is the top of the library: the run with its observers, scenarios, the executor.
    graph = package_graph(import_graph(PINWIND, "pinwind"), "pinwind")
    importers = {package for package, imported in graph.items() if "pinwind.runs" in imported}
    assert importers == {"pinwind.testing", "pinwind.cli"}


def test_the_run_imports_nothing_of_the_modes() -> None:
    # The modes sit above the run (pinwind/modes/__init__.py): dynamics keeps what a run needs.
    graph = package_graph(import_graph(PINWIND, "pinwind"), "pinwind")
    assert "pinwind.dynamics" in graph["pinwind.modes"]
    assert "pinwind.modes" not in graph["pinwind.dynamics"]


def test_a_loop_of_packages_without_a_module_cycle_is_found(tmp_path: Path) -> None:
    pkg = tmp_path / "pkg"
    for folder in ("a", "b"):
        (pkg / folder).mkdir(parents=True)
        (pkg / folder / "__init__.py").write_text("")
    (pkg / "__init__.py").write_text("from pkg.a.x import X\n")
    (pkg / "a" / "x.py").write_text("from pkg.b.y import Y\n\nX = Y\n")
    (pkg / "a" / "z.py").write_text("Z = 1\n")
    (pkg / "b" / "y.py").write_text("Y = 1\n")
    (pkg / "b" / "w.py").write_text("from pkg.a.z import Z\n\nW = Z\n")
    graph = import_graph(pkg, "pkg")
    assert find_cycle(graph) is None
    packages = package_graph(graph, "pkg")
    assert packages == {"pkg.a": {"pkg.b"}, "pkg.b": {"pkg.a"}}
    assert find_cycle(packages) == ["pkg.a", "pkg.b", "pkg.a"]


def test_a_cycle_through_a_package_init_is_found(tmp_path: Path) -> None:
    # The shape of dynamics ↔ loads: core/__init__ imports core.run, which imports laws.law,
    # which imports core.native only to type-check; that runs core/__init__ again.
    pkg = tmp_path / "pkg"
    for folder in ("core", "laws"):
        (pkg / folder).mkdir(parents=True)
        (pkg / folder / "__init__.py").write_text("")
    (pkg / "__init__.py").write_text("")
    (pkg / "core" / "__init__.py").write_text("from pkg.core.run import run\n")
    (pkg / "core" / "native.py").write_text("SPEC = 1\n")
    (pkg / "core" / "run.py").write_text("import os\n\nfrom pkg.laws.law import Law\n")
    (pkg / "laws" / "law.py").write_text(
        "from typing import TYPE_CHECKING\n\nif TYPE_CHECKING:\n    from pkg.core import native\n"
    )
    graph = import_graph(pkg, "pkg")
    assert graph["pkg.core.run"] == {"pkg.laws", "pkg.laws.law"}
    assert graph["pkg.laws.law"] == {"pkg.core", "pkg.core.native"}
    assert find_cycle(graph) == ["pkg.core", "pkg.core.run", "pkg.laws.law", "pkg.core"]
    known = {("pkg.laws.law", "pkg.core.native")}
    assert find_cycle(import_graph(pkg, "pkg", known=known)) is None


def test_a_relative_import_inside_a_function_closes_a_cycle(tmp_path: Path) -> None:
    pkg = tmp_path / "pkg"
    (pkg / "sub").mkdir(parents=True)
    (pkg / "__init__.py").write_text("")
    (pkg / "a.py").write_text("from pkg.sub.b import B\n\nA = 1\n")
    (pkg / "sub" / "__init__.py").write_text("")
    (pkg / "sub" / "b.py").write_text("def f():\n    from .. import a\n    return a\n\nB = 2\n")
    graph = import_graph(pkg, "pkg")
    assert graph["pkg.a"] == {"pkg.sub", "pkg.sub.b"}
    assert graph["pkg.sub.b"] == {"pkg.a"}
    assert find_cycle(graph) == ["pkg.a", "pkg.sub.b", "pkg.a"]


def test_an_acyclic_package_has_no_cycle(tmp_path: Path) -> None:
    # a imports b through the package; the package's own __init__ imports a: no cycle, since a
    # module runs after its package started (the parent is not an edge of its own modules).
    pkg = tmp_path / "pkg"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("from pkg.a import A\n")
    (pkg / "a.py").write_text("from pkg import b\n\nA = b.B\n")
    (pkg / "b.py").write_text("B = 1\n")
    graph = import_graph(pkg, "pkg")
    assert graph["pkg"] == {"pkg.a"}
    assert graph["pkg.a"] == {"pkg.b"}
    assert find_cycle(graph) is None
