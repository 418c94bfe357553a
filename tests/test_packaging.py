"""The install's files agree: the build requirements the README installs are pyproject's."""

from __future__ import annotations

import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _requirements(lines: list[str]) -> set[str]:
    return {line.split("#")[0].replace(" ", "") for line in lines if line.split("#")[0].strip()}


def test_the_build_requirements_file_is_pyprojects_build_system_with_cmake_and_ninja():
    declared = tomllib.loads((ROOT / "pyproject.toml").read_text())["build-system"]["requires"]
    listed = _requirements((ROOT / "requirements-build.txt").read_text().splitlines())
    extra = {r for r in listed if r.split(">")[0].split("<")[0] in ("cmake", "ninja")}
    assert listed - extra == _requirements(declared)
    assert {r.split(">")[0] for r in extra} == {"cmake", "ninja"}


def test_the_readme_and_ci_install_the_build_requirements_then_build_without_isolation():
    install = (
        ".venv/bin/pip install -r requirements-build.txt && "
        '.venv/bin/pip install --no-build-isolation -v -e ".[test]"'
    )
    readme = (ROOT / "README.md").read_text()
    assert readme.count(install) == 2  # the main job's command and the tests'
    assert install in (ROOT / ".ci" / "run").read_text()
