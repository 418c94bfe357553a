"""LDD and LRD of a fatigue set over the site's life (IEC 61400-4), from its case logs."""

from __future__ import annotations

import csv

import numpy as np
from numpy.testing import assert_allclose

from pinwind import read_log
from pinwind.runs.case_runner import run_cases
from pinwind.runs.fatigue_set_file import load_fatigue_set
from pinwind.runs.set_load_spectra import set_load_spectra, write_load_spectra_csv
from tests.conftest import fatigue_toml


def test_set_ldd_sums_to_the_sites_hours_and_lrd_to_each_bins_revolutions(tmp_path):
    # Two bins of 1000 h and 250 h, one seed: every shaft's LDD holds the 1250 h; its LRD the
    # revolutions of each case's counted history, ∫|ω| dt / 2π by numpy's trapezoid, scaled to
    # its bin's hours.
    fset = load_fatigue_set(fatigue_toml(tmp_path, fatigue="skip_start = 0.01"))
    run_cases(fset, workers=1)
    spectra = set_load_spectra(fset, 0, bins=7)
    expected: dict[str, float] = {}
    for case in fset.cases():
        res = read_log(fset.log_path(case))
        counted = res.time >= 0.01
        t = res.time[counted]
        hours = fset.site.bins[case.bin].hours
        for i, joint in enumerate(res.joint_names):
            turns = np.trapezoid(np.abs(res.speed[counted, i]), t) / (2 * np.pi)
            expected[joint] = expected.get(joint, 0.0) + turns * hours * 3600.0 / (t[-1] - t[0])
    assert {s.joint for s in spectra} <= set(expected) and len(spectra) >= 2
    for spectrum in spectra:
        assert len(spectrum.time) == 7
        assert_allclose(spectrum.time.sum(), 1250.0 * 3600.0, rtol=1e-12)
        assert_allclose(spectrum.revolutions.sum(), expected[spectrum.joint], rtol=1e-9)
    carrier = next(s for s in spectra if s.joint == "carrier")
    assert carrier.revolutions.sum() > 0.0

    written = write_load_spectra_csv(spectra, tmp_path / "ls.csv")
    rows = list(csv.DictReader(written.read_text(encoding="utf-8").splitlines()))
    assert len(rows) == 7 * len(spectra)
    hours = sum(float(r["time_h"]) for r in rows if r["joint"] == "carrier")
    assert_allclose(hours, 1250.0, rtol=1e-12)
