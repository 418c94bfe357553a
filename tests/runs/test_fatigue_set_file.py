"""Fatigue set files (``runs/fatigue_set_file.py``): the bins' hours, the rotor, the S-N presets,
materials and root tables per gear or role, and bad input refused naming its key."""

from __future__ import annotations

import math

import pytest
from numpy.testing import assert_allclose

from pinwind.dynamics.elements import rotor_power_coefficient
from pinwind.loads.rotor import JORGENSEN2014_POWER_CURVE, Rotor
from pinwind.runs.fatigue_set_file import load_fatigue_set
from pinwind.runs.scenario import ScenarioError
from tests.conftest import fatigue_toml
from tests.life.test_set_damage import iso_toml


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


@pytest.mark.parametrize("quick", [False, True], ids=["set", "quick"])
def test_a_set_without_duration_is_refused_naming_the_key_and_the_fix(tmp_path, quick):
    """It used to run 30 s per case without a word (issue 39). A duration in [fatigue.quick]
    alone does not count: the set itself must say how long its cases are."""
    path = fatigue_toml(tmp_path)
    text = path.read_text()
    assert "duration = 0.04\n" in text
    text = text.replace("duration = 0.04\n", "") + "[fatigue.quick]\nduration = 0.02\n"
    path.write_text(text)
    with pytest.raises(ScenarioError) as caught:
        load_fatigue_set(path, quick=quick)
    error = caught.value
    assert error.key == "fatigue.duration"
    assert error.path == str(path)
    # The line is the [fatigue] table's, the nearest parent of the missing key.
    assert error.line == [line.strip() for line in text.splitlines()].index("[fatigue]") + 1
    assert "missing: give the simulated seconds per case in the [fatigue] table" in str(error)
    assert "e.g. duration = 30.0" in str(error)


def test_gears_rates_the_named_gears_only_and_refuses_an_unknown_one(tmp_path):
    path = fatigue_toml(tmp_path)
    rated = load_fatigue_set(path, fatigue=_fatigue_table(path, gears=["sun", "planet2"]))
    assert rated.gears == ("sun", "planet2")
    with pytest.raises(ScenarioError, match=r"fatigue\.gears: sunn: no meshed gear .* sun, "):
        load_fatigue_set(path, fatigue=_fatigue_table(path, gears=["sunn"]))


def _fatigue_table(path, **changes):
    """The [fatigue] table of a set file, with changes: a plain scenario's set."""
    import tomllib

    return {**tomllib.loads(path.read_text())["fatigue"], **changes}


def test_a_case_duration_of_more_steps_than_a_run_takes_is_refused_before_any_case(tmp_path):
    # 1e30 s at dt = 2e-5 s is 5e34 steps per case; it failed inside the wind's synthesis with
    # numpy's "ValueError: Maximum allowed size exceeded".
    path = fatigue_toml(tmp_path)
    text = path.read_text()
    assert "duration = 0.04\n" in text
    path.write_text(text.replace("duration = 0.04\n", "duration = 1e30\n"))
    with pytest.raises(ScenarioError) as info:
        load_fatigue_set(path)
    message = str(info.value)
    assert "fatigue.duration: is 1e+30 s: 5e+34 steps of dt = 2e-05 s per case" in message
    assert message.startswith(f"{path}:")
