"""Palmgren's factors against the one text that could be read, and the docs' table against the code.

The text: C. Fernandes (University of Porto), machine-elements course figure script
``figures/RB_L3_Palmgren.py`` (github cfernandesFEUP/Machine-Elements-Animations-Figures,
commit 40f90ec), function ``Harris``: a 6206 deep-groove ball bearing (D 62, d 30 mm),
"f0 = 1.75 ## 1.5-2", M0 = f0 1e-7 (ν n)^(2/3) d_m³ [N·mm], ν = 20 mm²/s, n = 3000 rpm.
Every other row of ``PALMGREN_FACTORS`` could not be checked and must say so (docs/losses.md).
"""

from __future__ import annotations

import math
import re
from pathlib import Path

from numpy.testing import assert_allclose

from pinwind.losses.bearing_friction import PALMGREN_FACTORS, no_load_moment

ROOT = Path(__file__).resolve().parents[2]
RPM = 2.0 * math.pi / 60.0


def test_deep_groove_ball_f0_is_the_middle_of_the_range_read_in_the_lecture_script():
    low, high = 1.5, 2.0  # the script's comment "## 1.5-2"
    factors = PALMGREN_FACTORS["deep_groove_ball"]
    assert factors.f0 == (low + high) / 2.0
    assert "RB_L3_Palmgren.py" in factors.source


def test_deep_groove_ball_viscous_moment_at_the_scripts_6206_point_by_hand():
    # d_m = (62 + 30)/2 = 46 mm; ν n = 20 × 3000 = 6e4 ≥ 2000: the viscous branch.
    # (6e4)^(2/3) = 1532.619; 46³ = 97 336; M0 = 1.75e-7 × 1532.619 × 97 336 = 26.106 N·mm.
    m0_nmm = 1.75e-7 * 1532.619 * 97336.0
    moment = no_load_moment(PALMGREN_FACTORS["deep_groove_ball"].f0, 20e-6, 3000.0 * RPM, 0.046)
    assert_allclose(moment, m0_nmm * 1e-3, rtol=1e-6)


def test_every_row_says_where_its_factors_come_from_or_that_they_are_unchecked():
    for kind, factors in PALMGREN_FACTORS.items():
        source = factors.source
        read = "RB_L3_Palmgren.py" in source
        assert read or "unverified" in source or "assumption" in source, (kind, source)
    checked = [kind for kind, f in PALMGREN_FACTORS.items() if "RB_L3_Palmgren.py" in f.source]
    assert checked == ["deep_groove_ball"]


def test_the_docs_factor_table_is_the_codes():
    text = (ROOT / "docs" / "losses.md").read_text(encoding="utf-8")
    rows = re.findall(r"^\| `(\w+)` \| ([\d.]+) \| ([\d.]+) \| (.+) \|$", text, flags=re.MULTILINE)
    table = {kind: (float(f0), float(f1), note) for kind, f0, f1, note in rows}
    assert set(table) == set(PALMGREN_FACTORS)
    for kind, factors in PALMGREN_FACTORS.items():
        f0, f1, note = table[kind]
        assert (f0, f1) == (factors.f0, factors.f1), kind
        # a row the code calls unverified is "not checked" in the docs, and the other way round
        assert factors.source.startswith("unverified") == (note == "not checked"), kind
