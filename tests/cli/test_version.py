"""``pinwind --version``: the version of the installed distribution, or that none is installed."""

from __future__ import annotations

import importlib.metadata

from typer.testing import CliRunner

from pinwind.cli import app


def test_version_prints_the_installed_distributions_version(monkeypatch):
    monkeypatch.setattr(importlib.metadata, "version", lambda name: "9.8.7")
    out = CliRunner().invoke(app, ["--version"])
    assert out.exit_code == 0
    assert out.output.strip() == "pinwind 9.8.7"


def test_version_says_not_installed_when_run_from_a_source_tree(monkeypatch):
    def missing(name: str) -> str:
        raise importlib.metadata.PackageNotFoundError(name)

    monkeypatch.setattr(importlib.metadata, "version", missing)
    out = CliRunner().invoke(app, ["--version"])
    assert out.exit_code == 0
    assert "not installed" in out.output
