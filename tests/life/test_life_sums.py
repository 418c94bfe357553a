"""Modified and reference lives over a site, and a row's load zone: ISO 281 and Harris by hand."""

from __future__ import annotations

import math
import warnings

import numpy as np
from numpy.testing import assert_allclose

from pinwind.life.case_cycles import CaseCycles
from pinwind.life.life_sums import history_sums
from pinwind.life.set_bearing_life import set_bearing_lives
from pinwind.model.bearing_life_data import BearingLifeData
from pinwind.runs.fatigue_set_file import load_fatigue_set
from tests.conftest import fatigue_toml

RPM = 2.0 * math.pi / 60.0
#: planet1's data in the cases below: D d B 300/200/60 mm (d_m 250 mm), C_u 50 kN, e_C 0.5,
#: ν 80 mm²/s at the operating temperature (given outright).
SIZE, C_U, E_C, NU_MM2S = (0.30, 0.20, 0.06), 50e3, 0.5, 80.0
DATA = BearingLifeData(size=SIZE, fatigue_limit=C_U, contamination=E_C, viscosity=NU_MM2S * 1e-6)
#: The two bins of `fatigue_toml` (10 m/s 1000 h, 16 m/s 250 h): planet1's radial load [N] and
#: speed [rpm] in each.
BINS = ((1000.0, 200e3, 60.0), (250.0, 400e3, 90.0))


def a_iso_roller(kappa: float, x: float) -> float:
    """ISO 281:2007 §9.3.2's a_ISO of a radial roller bearing, x = e_C C_u / P, 0.1 ≤ κ ≤ 4."""
    if kappa < 0.4:
        c2, c3 = 1.3993, 0.054381
    elif kappa < 1.0:
        c2, c3 = 1.2348, 0.19087
    else:
        c2, c3 = 1.2348, 0.071739
    return min(0.1 * (1.0 - (1.5859 - c2 * kappa**-c3) * x**0.4) ** -9.185, 50.0)


def hand_lives(rating_n: float) -> dict[str, float]:
    """planet1's L10h and L_nmh [h] over the two bins, by ISO 281 (p = 10/3, P = F_r)."""
    p = 10.0 / 3.0
    dm_mm = 0.5 * (SIZE[0] + SIZE[1]) * 1e3
    revolutions = used = used_modified = 0.0
    for hours, load, rpm in BINS:
        nu1 = 45000.0 * rpm**-0.83 * dm_mm**-0.5  # n < 1000 r/min [mm²/s]
        a = a_iso_roller(NU_MM2S / nu1, E_C * C_U / load)
        turns = hours * 60.0 * rpm
        l10 = (rating_n / load) ** p  # [10⁶ rev]
        revolutions += turns
        used += turns / (l10 * 1e6)  # Palmgren-Miner on revolutions
        used_modified += turns / (a * l10 * 1e6)
    per_hour = revolutions / sum(h for h, _, _ in BINS)
    return {
        "l10h": revolutions / used / per_hour,
        "lnmh": revolutions / used_modified / per_hour,
    }


def write_cases(fset) -> None:
    """Each case's reduction: planet1 at its bin's constant radial load and speed."""
    for case, (_, load, rpm) in zip(fset.cases(), BINS, strict=True):
        time = np.linspace(0.0, 2.0, 401)
        w = np.zeros((len(time), 5))
        w[:, 0] = load  # F_u: along a roller (the calibration case)
        history = history_sums(
            "planet1", fset.bearings["planet1"], data=DATA, size=None, time=time,
            speed=np.full(len(time), rpm * RPM), load=w,
        )  # fmt: skip
        fset.out.mkdir(parents=True, exist_ok=True)
        reduced = CaseCycles(case, fset.case_key(case), 2.0, 0.0, bearings=(history.sums,))
        reduced.save(fset.cycles_path(case))


def test_modified_life_over_two_bins_is_miner_of_a_iso_times_each_bins_basic_life(tmp_path):
    fset = load_fatigue_set(fatigue_toml(tmp_path))
    write_cases(fset)
    (life,) = set_bearing_lives(fset)[0]
    c = fset.bearings["planet1"].dynamic_load_rating
    expected = hand_lives(c)
    assert_allclose(life.l10h, expected["l10h"], rtol=1e-9)
    assert_allclose(life.lnmh, expected["lnmh"], rtol=1e-9)
    # a_ISO below 1 at these loads and oils: the modified life is the shorter
    assert life.lnmh < 0.9 * life.l10h
    assert_allclose(life.as_dict()["lnm_h"], expected["lnmh"], rtol=1e-9)


def test_reference_life_in_the_calibration_case_is_the_basic_life(tmp_path):
    # Pure radial loads, no clearance, no tilt: ISO/TS 16281's P_ref is F_r, so L10r = L10
    # (within its discretisation of the rollers; ISO/TS 16281:2008 §6 calibration).
    fset = load_fatigue_set(fatigue_toml(tmp_path))
    write_cases(fset)
    (life,) = set_bearing_lives(fset)[0]
    assert math.isfinite(life.l10rh)
    assert_allclose(life.l10r, life.l10, rtol=1e-2)
    assert_allclose(life.l10rh, hand_lives(fset.bearings["planet1"].dynamic_load_rating)["l10h"],
                    rtol=1e-2)  # fmt: skip


def test_a_bearing_without_size_or_fatigue_limit_has_no_modified_or_reference_life(tmp_path):
    fset = load_fatigue_set(fatigue_toml(tmp_path))
    time = np.linspace(0.0, 1.0, 101)
    w = np.zeros((len(time), 5))
    w[:, 1] = 1e5
    for data, lnm, l10r in (
        (None, False, False),  # no size: neither
        (BearingLifeData(size=SIZE), False, True),  # no C_u nor C₀: no modified life
        (BearingLifeData(size=SIZE, static_rating=2e6), True, True),  # C_u estimated from C₀
    ):
        history = history_sums("planet1", fset.bearings["planet1"], data=data, size=None,
                               time=time, speed=np.full(len(time), 60 * RPM), load=w)  # fmt: skip
        assert math.isnan(history.sums.modified_sum) != lnm
        assert math.isnan(history.sums.reference_sum) != l10r
        if not lnm:
            assert any("no modified life" in note for note in history.notes)


def test_a_rows_load_zone_and_largest_roller_load_under_a_radial_load_are_stribecks():
    # A shaft on two rows (tests/analysis/test_bearing_rows.py) under a radial hub load: no tilt
    # springs, no axial load, no clearance. Row B (cylindrical, 300/200/60 mm: Z = ⌊0.85 π
    # d_m / D_we⌋ = ⌊0.85 π 250 / 25⌋ = 26 rollers) has a zone of 180° (ψ_l = ±90°) and
    # Q_max = 4.08 F_r / Z (Stribeck's line-contact constant, Harris and Kotzalas 2007 §7.3)
    # at each sample; row A has no size: NaN.
    import pinwind
    from pinwind.errors import PinwindWarning
    from pinwind.loads.hub_loads import constant_hub_load
    from pinwind.model.gearbox import loads
    from tests.analysis.test_bearing_rows import _rows, shaft_on_rows

    text = shaft_on_rows(_rows(k=1e9))
    text = text.replace('position_mm="100.0"', 'position_mm="100.0" size_mm="300 200 60"')
    assert 'size_mm="300 200 60"' in text
    gb = loads(text, path="shaft.urdf")
    load = constant_hub_load("shaft", [0, 0, -1e5, 0, 0, 0], point=(0, 0, 0), up=(0, 1, 0))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PinwindWarning)
        res = pinwind.simulate(
            gb, duration=0.02, dt=1e-3, hub_loads=[load], speeds={"shaft": 30 * RPM}
        )
    a, b = res.row_names.index("shaft.A"), res.row_names.index("shaft.B")
    radial = np.hypot(res.row_force[:, b, 0], res.row_force[:, b, 1])
    loaded = radial > 1e3
    assert loaded.sum() >= 10
    assert_allclose(np.degrees(res.row_load_zone[loaded, b]), 180.0, rtol=1e-9)
    assert_allclose(res.row_max_element_load[loaded, b], 4.08 * radial[loaded] / 26, rtol=1e-2)
    assert np.all(np.isnan(res.row_load_zone[:, a])) and np.all(
        np.isnan(res.row_max_element_load[:, a])
    )


def test_a_rows_lives_are_the_same_from_pinwind_life_and_from_a_fatigue_cases_sums():
    # One rating and one set of sums per row (issue 38): `row_lives` (pinwind life) and the
    # sums a fatigue case keeps (`run_load_sums`, rated by `life_of_load_sum`) agree.
    from pinwind.life.bearing_life import life_of_load_sum, row_ratings
    from pinwind.life.life_sums import run_load_sums
    from pinwind.life.row_life import row_lives
    from tests.life.test_row_life import run_shaft, shaft_text

    res, gb = run_shaft(shaft_text())
    sums = {s.joint: s for s in run_load_sums(res, gb)}
    ratings = row_ratings(gb)
    for row in row_lives(res, gb):
        name = f"{row.bearing}.{row.name}"
        life = life_of_load_sum(ratings[name], sums[name])
        assert ratings[name].dynamic_load_rating == row.rating
        assert_allclose(life.l10h, row.l10h, rtol=1e-12)
        assert_allclose(life.lnmh, row.lnmh, rtol=1e-12)  # a₁ = 1 at 90 %
        assert_allclose(life.l10rh, row.l10rh, rtol=1e-12)
        assert math.isfinite(row.lnmh) and math.isfinite(row.l10rh)
