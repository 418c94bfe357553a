"""A fatigue set's cases run (``runs/case_runner.py``): a rerun computes only the missing or
damaged cases, and Dask gives the damage of a run in this process."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest
from numpy.testing import assert_allclose

from pinwind.life.case_cycles import CaseCycles
from pinwind.life.set_damage import set_damage
from pinwind.runs.case_runner import run_cases
from pinwind.runs.fatigue_set_file import load_fatigue_set
from tests.conftest import fatigue_toml


def test_rerun_computes_only_the_case_whose_log_was_deleted(tmp_path, monkeypatch):
    import pinwind.runs.case_runner as case_runner

    calls = []
    original = case_runner.run_saved_case

    def counted(case, fatigue):
        calls.append(case.name)
        return original(case, fatigue)

    monkeypatch.setattr(case_runner, "run_saved_case", counted)
    fset = load_fatigue_set(fatigue_toml(tmp_path))
    first = run_cases(fset, workers=1)
    assert sorted(first.computed) == sorted(c.name for c in fset.cases())
    gone = fset.cases()[1]
    fset.log_path(gone).unlink()
    second = run_cases(fset, workers=1)
    assert second.computed == [gone.name]
    assert calls == [*first.computed, gone.name]
    assert run_cases(fset, workers=1).computed == []
    assert set_damage(fset).damage["no limit"][0]["sun"].total > 0.0


def test_dask_backend_gives_the_damage_of_a_run_in_this_process(tmp_path):
    distributed = pytest.importorskip("distributed")
    here = load_fatigue_set(fatigue_toml(tmp_path))
    run_cases(here, workers=1)
    there = dataclasses.replace(here, out=tmp_path / "dask")
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                  dashboard_address=None) as cluster:  # fmt: skip
        with distributed.Client(cluster) as client:
            run = run_cases(there, scheduler=client)
    assert run.backend.startswith("dask") and len(run.computed) == 2
    for variant in ("limit", "no limit"):
        a = set_damage(here).damage[variant][0]
        b = set_damage(there).damage[variant][0]
        for gear in a:
            assert_allclose(b[gear].per_bin, a[gear].per_bin, rtol=0, atol=0)


def _flip_a_byte(path: Path) -> None:
    """Flip every bit of the byte in the middle of a file (as a bad disk or copy does)."""
    data = bytearray(path.read_bytes())
    data[len(data) // 2] ^= 0xFF
    path.write_bytes(bytes(data))


@pytest.mark.parametrize("which", ["log", "reduction"])
def test_a_flipped_byte_in_a_kept_case_file_has_the_case_computed_again_with_a_warning(
    tmp_path, which
):
    """A flipped byte in a kept log was reused without a word; one in a kept reduction made
    every rerun fail with BadZipFile, naming no file."""
    from pinwind.errors import CaseFileDamaged
    from pinwind.runs.case_runner import file_sha256

    fset = load_fatigue_set(fatigue_toml(tmp_path))
    run_cases(fset, workers=1)
    case = fset.cases()[0]
    path = fset.log_path(case) if which == "log" else fset.cycles_path(case)
    _flip_a_byte(path)
    with pytest.warns(CaseFileDamaged, match=f"{path}: the kept .* of case {case.name}") as caught:
        again = run_cases(fset, workers=1)
    assert caught[0].filename == __file__  # said at the caller of run_cases
    assert again.computed == [case.name]
    # Whole again: the log is the one the new reduction was made from.
    assert CaseCycles.load(fset.cycles_path(case)).log_sha256 == file_sha256(fset.log_path(case))
    assert run_cases(fset, workers=1).computed == []
