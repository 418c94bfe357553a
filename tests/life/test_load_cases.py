"""Fatigue sets: hours of the bins, damage from the cases' cycles by hand, resumability, bad input.

The damage of a set is checked against Palmgren-Miner by hand on cycles written here: with
N(s) = N0 (s0 / s)^m, a cycle of range s counts (s / s0)^m / N0, times the bin's
h · 3600 / T_counted.
"""

from __future__ import annotations

import dataclasses
import math
import textwrap
from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose

from pinwind.dynamics.elements import rotor_power_coefficient
from pinwind.life.case_cycles import CaseCycles, FlankCycles
from pinwind.life.case_runner import run_cases
from pinwind.life.fatigue_set_file import load_fatigue_set
from pinwind.life.set_damage import set_damage
from pinwind.loads.rotor import JORGENSEN2014_POWER_CURVE, Rotor
from pinwind.scenario import ScenarioError
from tests.conftest import MODELS

MODEL = (MODELS / "dtu500_planetary.urdf").as_posix()


def fatigue_toml(tmp_path: Path, fatigue: str = "", run: str = "", site: str = "") -> Path:
    """A fatigue set of the DTU 500 kW stage: two bins, one level, one seed, 0.04 s cases."""
    site = site or "speeds = [10, 16]\nhours = [1000, 250]"
    text = textwrap.dedent(
        f"""\
        model = "{MODEL}"
        dt = 2e-5
        initial_speed = {{ carrier = 27.1 }}
        log_rate = 1000.0
        {run}
        [rotor.carrier]
        preset = "jorgensen2014"

        [generator.sun]
        law = "linear-slip"
        slope = 203568.04
        sync_rpm = 148.91584

        [fatigue]
        out = "cases"
        duration = 0.04
        sample_rate = 50000.0
        turbulence = 0.1
        seeds = [3]
        hub_height = 36.0
        {fatigue}
        [fatigue.site]
        {site}

        [fatigue.sn_curve]
        s0_mpa = 1000.0
        m = 3.0
        endurance_limit_mpa = 0.0
        """
    )
    path = tmp_path / "set.toml"
    path.write_text(text)
    return path


def test_given_hours_per_bin_sum_to_the_sets_total(tmp_path):
    fset = load_fatigue_set(fatigue_toml(tmp_path, site="speeds = [6, 8, 10]\nhours = [4, 5, 6]"))
    assert_allclose(fset.site.total_hours, 15.0, rtol=0, atol=1e-12)
    assert len(fset.cases()) == 3


def test_weibull_site_hours_are_the_design_life_times_the_probability_in_range(tmp_path):
    site = "scale = 6.62\nshape = 2.19\nedges = [5, 7, 9]\ndesign_life_years = 20"
    fset = load_fatigue_set(fatigue_toml(tmp_path, site=site))
    # T [h] · (F(9) − F(5)), F(v) = 1 − exp(−(v/A)^k), by hand
    expected = 20 * 365 * 24 * (math.exp(-((5 / 6.62) ** 2.19)) - math.exp(-((9 / 6.62) ** 2.19)))
    assert_allclose(fset.site.total_hours, expected, rtol=1e-12)


def test_jorgensen2014_rotor_gives_its_power_curve_at_27_1_rpm():
    rotor = Rotor.jorgensen2014()
    omega = 27.1 * 2 * math.pi / 60
    for wind, power_kw in JORGENSEN2014_POWER_CURVE[2:-2]:
        cp = rotor_power_coefficient(rotor, omega * rotor.radius / wind)
        power = 0.5 * 1.225 * math.pi * 20.5**2 * wind**3 * cp
        assert_allclose(power, power_kw * 1e3, rtol=1e-9)


def write_cycles(fset, case, tooth, ranges_mpa, counts, counted_seconds):
    """A case reduction for the sun (20 teeth, one flank) with these cycles."""
    flank = FlankCycles(
        gear="sun",
        flank=1,
        teeth=20,
        tooth=np.asarray(tooth),
        ranges=np.asarray(ranges_mpa, dtype=float) * 1e6,
        counts=np.asarray(counts, dtype=float),
        peaks=np.zeros(20),
    )
    fset.out.mkdir(parents=True, exist_ok=True)
    CaseCycles(case, fset.case_key(case), counted_seconds, 0.0, (flank,)).save(
        fset.cycles_path(case)
    )


def test_two_case_set_damage_is_the_sum_of_the_cases_miner_sums_by_hand(tmp_path):
    fset = load_fatigue_set(fatigue_toml(tmp_path))
    low, high = fset.cases()  # 10 m/s (1000 h), 16 m/s (250 h)
    write_cycles(fset, low, [4, 4, 7], [500, 300, 800], [1.0, 0.5, 1.0], 2.0)
    write_cycles(fset, high, [4, 7], [600, 900], [2.0, 1.0], 4.0)
    damage = set_damage(fset).damage["no limit"][0]["sun"]
    # tooth 4: (0.5³ + 0.5·0.3³)·1000·3600/2 + 2·0.6³·250·3600/4
    tooth_4 = (0.5**3 + 0.5 * 0.3**3) * 1000 * 1800 + 2 * 0.6**3 * 250 * 900
    # tooth 7: 0.8³·1000·3600/2 + 0.9³·250·3600/4
    tooth_7 = 0.8**3 * 1000 * 1800 + 0.9**3 * 250 * 900
    assert damage.tooth == (4 if tooth_4 > tooth_7 else 7)
    assert_allclose(damage.total, max(tooth_4, tooth_7), rtol=1e-12)
    worst = (0.5**3 + 0.5 * 0.3**3, 2 * 0.6**3) if tooth_4 > tooth_7 else (0.8**3, 0.9**3)
    assert_allclose(damage.per_bin, [worst[0] * 1000 * 1800, worst[1] * 250 * 900], rtol=1e-12)


def test_cycles_below_the_endurance_limit_do_no_damage_in_a_set(tmp_path):
    fset = load_fatigue_set(fatigue_toml(tmp_path))
    limited = {g: dataclasses.replace(c, endurance_limit=850e6) for g, c in fset.curves.items()}
    fset = dataclasses.replace(fset, curves=limited)
    low, high = fset.cases()
    write_cycles(fset, low, [1], [840], [1.0], 1.0)
    write_cycles(fset, high, [1], [860], [1.0], 1.0)
    damage = set_damage(fset).damage["limit"][0]["sun"]
    assert_allclose(damage.per_bin, [0.0, 0.86**3 * 250 * 3600], rtol=1e-12)


def flank(gear, side, teeth, tooth, ranges_mpa, counts):
    """Cycles of one flank (or its root fillet) of a gear."""
    return FlankCycles(
        gear=gear,
        flank=side,
        teeth=teeth,
        tooth=np.asarray(tooth),
        ranges=np.asarray(ranges_mpa, dtype=float) * 1e6,
        counts=np.asarray(counts, dtype=float),
        peaks=np.zeros(teeth),
    )


def iso_toml(tmp_path: Path, sn_curve: str) -> Path:
    """The two-bin set with another ``[fatigue.sn_curve]`` table."""
    path = fatigue_toml(tmp_path)
    text = path.read_text()
    start = text.index("[fatigue.sn_curve]")
    path.write_text(text[:start] + "[fatigue.sn_curve]\n" + sn_curve)
    return path


# ISO 6336 for 18CrNiMo7-6 (case carburised; σ_Hlim 1500, σ_Flim 500 MPa), by hand:
# contact, Table 2: Z_NT from 1.6 at 10⁵ to 1 at 5·10⁷, so N(Z) = 5·10⁷ Z^(−ln 500 / ln 1.6),
# read at σ_vM = 0.65 σ_H; root, Table 3: σ_FE = 2 σ_Flim = 1000 MPa, Y_NT from 2.5 at 10³ to
# 1 at 3·10⁶, N(Y) = 3·10⁶ Y^(−ln 3000 / ln 2.5); reversed bending (both flanks): 0.7 σ_FE.


def contact_life(z_nt: float) -> float:
    return 5e7 * z_nt ** (-math.log(500.0) / math.log(1.6))


def root_life(y_nt: float) -> float:
    return 3e6 * y_nt ** (-math.log(3000.0) / math.log(2.5))


def test_iso_variant_damage_of_contact_and_root_cycles_by_hand(tmp_path):
    """One 16 m/s case (250 h, 4 s counted): a sun contact cycle at Z_NT = 1.3, a sun root
    cycle at Y_NT = 1.5 on one flank, and a planet root cycle at 1.5 · 0.7 σ_FE on each flank."""
    fset = load_fatigue_set(fatigue_toml(tmp_path))
    low, high = fset.cases()
    fset.out.mkdir(parents=True, exist_ok=True)
    CaseCycles(low, fset.case_key(low), 2.0, 0.0).save(fset.cycles_path(low))
    contact = (flank("sun", 1, 20, [2], [0.65 * 1.3 * 1500], [1.0]),)
    roots = (
        flank("sun", 1, 20, [2], [1500], [1.0]),
        flank("planet1", 1, 35, [5], [0.7 * 1.5 * 1000], [1.0]),
        flank("planet1", -1, 35, [5], [0.7 * 1.5 * 1000], [1.0]),
    )
    CaseCycles(high, fset.case_key(high), 4.0, 0.0, contact, roots).save(fset.cycles_path(high))
    damage = set_damage(fset)
    time_factor = 250 * 3600 / 4.0
    sun = damage.damage["iso 6336"][0]["sun"]
    assert_allclose(sun.per_bin, [0.0, time_factor / contact_life(1.3)], rtol=1e-9)
    root = damage.root_damage["iso 6336"][0]
    assert_allclose(root["sun"].total, time_factor / root_life(1.5), rtol=1e-9)
    assert_allclose(root["planet1"].total, time_factor / root_life(1.5), rtol=1e-9)
    assert root["sun"].tooth == 2 and root["planet1"].tooth == 5
    # The set's own curve (N = (1000 MPa / s)³) rates the root cycles as it rates the contact.
    assert_allclose(
        damage.root_damage["no limit"][0]["sun"].total, 1.5**3 * time_factor, rtol=1e-12
    )


def test_iso6336_preset_rates_contact_and_root_with_iso_curves(tmp_path):
    """preset = "iso6336" with σ_Hlim = 1400 MPa for the sun: its contact curve reaches
    0.65 · 1400 MPa at 5·10⁷ cycles; its root curve σ_FE = 1000 MPa at 3·10⁶."""
    fset = load_fatigue_set(
        iso_toml(tmp_path, 'preset = "iso6336"\nsigma_h_lim_mpa = { sun = 1400, planet = 1500, '
                 "ring = 1500 }\n")
    )  # fmt: skip
    assert_allclose(fset.curves["sun"].stress(5e7), 0.65 * 1400e6, rtol=1e-12)
    assert_allclose(fset.curves["ring"].stress(1e5), 0.65 * 1.6 * 1500e6, rtol=1e-12)
    assert_allclose(fset.root_curves["sun"].stress(3e6), 1000e6, rtol=1e-12)
    permitted = load_fatigue_set(iso_toml(tmp_path, 'preset = "iso6336_pitting_permitted"\n'))
    assert_allclose(permitted.curves["sun"].stress(1e7), 0.65 * 1.3 * 1500e6, rtol=1e-12)


def test_materials_set_the_iso_curves_per_gear_kind(tmp_path):
    """A through-hardened 42CrMo4 ring (σ_Hlim 770, σ_Flim 310 MPa): its ISO root curve is
    ISO 6336-3's St, V row, 2.5 at 10⁴ cycles."""
    path = fatigue_toml(tmp_path, fatigue='[fatigue.materials]\nring = "42CrMo4"\n')
    fset = load_fatigue_set(path)
    assert fset.materials["ring"] == "42CrMo4" and fset.materials["planet1"] == "18CrNiMo7-6"
    assert_allclose(fset.iso_root_curves["ring"].stress(1e4), 2.5 * 620e6, rtol=1e-12)
    assert_allclose(fset.iso_curves["ring"].stress(5e7), 0.65 * 770e6, rtol=1e-12)


def test_root_stress_table_changes_the_case_inputs(tmp_path):
    """A table for the sun replaces ISO 6336-3 there, and its cases' reductions are redone."""
    plain = load_fatigue_set(fatigue_toml(tmp_path))
    table = "[fatigue.root_stress]\nsun = { position_mm = [30, 50], mpa_per_kn = [2, 4] }\n"
    tabled = load_fatigue_set(fatigue_toml(tmp_path, fatigue=table))
    assert_allclose(tabled.root_stress["sun"].stress_per_force, [2e3, 4e3], rtol=1e-12)
    assert "ISO 6336-3" in tabled.root_stress["ring"].describe()
    case = plain.cases()[0]
    assert plain.case_key(case) != tabled.case_key(case)


@pytest.mark.parametrize(
    ("table", "message"),
    [
        ('[fatigue.materials]\nsun = "unobtainium"\n', '"unobtainium" (sun) is unknown'),
        (
            "[fatigue.root_stress]\nsun = { position_mm = [30], mpa_per_kn = [2] }\n",
            "two or more positions",
        ),
        ("[fatigue.root_stress]\nmoon = { fraction = [0, 1], mpa_per_kn = [2, 3] }\n", "moon"),
    ],
)
def test_bad_material_or_root_table_names_its_key(tmp_path, table, message):
    with pytest.raises(ScenarioError, match="fatigue") as caught:
        load_fatigue_set(fatigue_toml(tmp_path, fatigue=table))
    assert message in str(caught.value)


def test_rerun_computes_only_the_case_whose_log_was_deleted(tmp_path, monkeypatch):
    import pinwind.life.case_runner as case_runner

    calls = []
    original = case_runner.run_case

    def counted(case, fatigue):
        calls.append(case.name)
        return original(case, fatigue)

    monkeypatch.setattr(case_runner, "run_case", counted)
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


@pytest.mark.parametrize(
    ("fatigue", "site", "message"),
    [
        ("", "speeds = [10, 16]\nhours = [1000, nan]", "the hours of the 16 m/s bin is nan"),
        ("turbulence = -0.1", "", "turbulence intensity of the 10 m/s bin is -0.1"),
    ],
)
def test_bad_site_input_names_its_key(tmp_path, fatigue, site, message):
    text = fatigue_toml(tmp_path, site=site).read_text()
    if fatigue:
        text = text.replace("turbulence = 0.1", fatigue)
    (tmp_path / "set.toml").write_text(text)
    with pytest.raises(ScenarioError, match="fatigue") as caught:
        load_fatigue_set(tmp_path / "set.toml")
    assert message in str(caught.value)


def test_figures_of_a_set_are_written(tmp_path):
    from pinwind.life.life_figures import plot_damage_vs_turbulence, plot_range_cycles

    fset = load_fatigue_set(fatigue_toml(tmp_path))
    low, high = fset.cases()
    write_cycles(fset, low, [4], [500], [1.0], 2.0)
    write_cycles(fset, high, [4], [600], [1.0], 2.0)
    damage = set_damage(fset)
    for path in (
        plot_damage_vs_turbulence(damage, tmp_path / "figs" / "turbulence.png"),
        plot_range_cycles(damage, tmp_path / "figs" / "ranges.png"),
    ):
        assert path.stat().st_size > 1000


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


def test_damage_axis_draws_the_smallest_nonzero_damage_on_its_log_part():
    from pinwind.life.life_figures import damage_axis_threshold

    # ISO 6336 damages of 1e-44 beside Miner sums of hundreds: the linear range must end below
    # 3.1e-44, i.e. at the decade 1e-44; zeros and NaN do not move it.
    values = np.array([0.0, 641.0, 3.1e-44, 2.6e-8, np.nan])
    assert damage_axis_threshold(values) == pytest.approx(1e-44, rel=1e-12)
    assert damage_axis_threshold(np.array([0.0, 0.5])) == 1e-3
    assert damage_axis_threshold(np.zeros(3)) == 1e-3


# --- keys and rates that used to pass without a word (issue 43) ----------------------------------


@pytest.mark.parametrize(
    ("fatigue", "key", "meant"),
    [
        ("duraton = 0.02", "fatigue.duraton", "duration"),
        ("[fatigue.quick]\nduraton = 0.02", "fatigue.quick.duraton", "duration"),
        ('[fatigue.materials]\nrnig = "42CrMo4"', "fatigue.materials.rnig", "ring"),
        (
            "[fatigue.root_stress]\nsun = { position_mm = [30, 50], mpa_per_kn = [2, 4], "
            "fractoin = [0, 1] }",
            "fatigue.root_stress.sun.fractoin",
            "fraction",
        ),
    ],
    ids=["fatigue", "quick", "materials", "root-stress"],
)
def test_a_misspelt_fatigue_key_is_refused_naming_the_one_meant(tmp_path, fatigue, key, meant):
    with pytest.raises(ScenarioError) as caught:
        load_fatigue_set(fatigue_toml(tmp_path, fatigue=fatigue))
    assert caught.value.key == key
    assert f'did you mean "{meant}"?' in str(caught.value)


def test_a_misspelt_gear_in_a_per_gear_endurance_limit_is_refused_not_ignored(tmp_path):
    """``{ sun = 800, planet = 800, ring = 550, rnig = 1 }`` rated the ring at 550 MPa; the
    misspelt entry, meant for it, was never read."""
    path = fatigue_toml(tmp_path)
    text = path.read_text().replace(
        "endurance_limit_mpa = 0.0",
        "endurance_limit_mpa = { sun = 800, planet = 800, ring = 550, rnig = 1 }",
    )
    path.write_text(text)
    with pytest.raises(ScenarioError) as caught:
        load_fatigue_set(path)
    assert caught.value.key == "fatigue.sn_curve.endurance_limit_mpa.rnig"
    assert 'did you mean "ring"?' in str(caught.value)


def test_quick_on_a_set_without_a_quick_table_is_refused_not_run_whole(tmp_path):
    path = fatigue_toml(tmp_path)
    assert load_fatigue_set(path).duration == 0.04  # the set itself reads
    with pytest.raises(ScenarioError, match=r"has none, so it would run the whole set") as caught:
        load_fatigue_set(path, quick=True)
    assert caught.value.key == "fatigue.quick"


@pytest.mark.parametrize(
    ("rate", "said"),
    [
        # 1 / (3000 Hz · 20 µs) = 16.7 steps: read every 17th step, at 1 / (17 · 20 µs).
        (3000.0, "would be read at 2941.18 Hz; give a sample_rate that divides 1/dt = 50000 Hz"),
        (1e5, "sample_rate = 100000 Hz is above the step rate 1/dt = 50000 Hz"),
    ],
    ids=["not-dividing", "above-step-rate"],
)
def test_a_sample_rate_off_the_steps_is_refused_naming_the_rate_it_would_read(tmp_path, rate, said):
    path = fatigue_toml(tmp_path)
    path.write_text(path.read_text().replace("sample_rate = 50000.0", f"sample_rate = {rate!r}"))
    with pytest.raises(ScenarioError) as caught:
        load_fatigue_set(path)
    assert caught.value.key == "fatigue.sample_rate"
    assert said in str(caught.value)


def test_a_sample_rate_that_divides_the_step_rate_is_read_at_that_rate(tmp_path):
    """The control: 2500 Hz at dt = 20 µs is every 20th step, 2500 Hz exactly."""
    path = fatigue_toml(tmp_path)
    path.write_text(path.read_text().replace("sample_rate = 50000.0", "sample_rate = 2500.0"))
    fset = load_fatigue_set(path)
    keep = fset.case_values(fset.cases()[0])["keep"]
    assert keep == 20
    assert_allclose(1.0 / (keep * fset.dt), 2500.0, rtol=1e-12)


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
    from pinwind.life.case_runner import file_sha256

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
