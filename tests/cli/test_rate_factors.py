"""``pinwind rate`` factor options: application factor, accuracy, reliability and J by flag."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from typer.testing import CliRunner

from pinwind.cli import app
from pinwind.errors import InputError
from tests.conftest import MODELS
from tests.test_cli import run as run_cli

#: Saleh 2017's stage at its rated 1 MN·m on the carrier, the sun braked to balance, 14.2 rpm.
RATED = [
    "rate", str(MODELS / "saleh2017_planetary.urdf"), "--initial-speed", "carrier=14.2",
    "--torque", "carrier=1e6", "--torque", "sun=-166666.6666666667", "--duration", "0.01",
]  # fmt: skip


def rated(*options: str) -> dict:
    """The JSON of ``pinwind rate`` of the rated stage with these options."""
    out = CliRunner().invoke(app, [*RATED, *options, "--json"])
    assert out.exit_code == 0, out.output
    return json.loads(out.stdout)


@pytest.fixture(scope="module")
def default() -> dict:
    return rated()


def test_application_factor_scales_agma_root_stress_and_the_square_of_contact_stress(default):
    # AGMA 2001 loads the tooth with K_o W_t, its other factors independent of the load: root
    # stress ∝ K_o, Hertz contact stress ∝ √K_o.
    k = 1.5
    over = rated("--application-factor", str(k))
    for a, b in zip(default["meshes"], over["meshes"], strict=True):
        bending, contact = (np.array(a["agma"][q]) for q in ("bending_stress", "contact_stress"))
        np.testing.assert_allclose(b["agma"]["bending_stress"], k * bending, rtol=1e-12)
        np.testing.assert_allclose(b["agma"]["contact_stress"], math.sqrt(k) * contact, rtol=1e-12)


def test_application_factor_multiplies_iso_nominal_stresses_with_the_other_load_factors(default):
    # ISO 6336-3 eq. (3), 6336-2 eq. (2): σ_F = σ_F0 K_A K_v K_Fβ K_Fα, σ_H = σ_H0 √(K_A K_v K_Hβ
    # K_Hα); K_v and K_Hβ depend on the load K_A F_t/b, the nominal σ_F0 and σ_H0 do not.
    over = rated("--application-factor", "1.5")
    for a, b in zip(default["meshes"], over["meshes"], strict=True):
        f = b["iso"]["factors"]
        assert f["K_A"] == 1.5
        np.testing.assert_allclose(b["iso"]["sigma_F0"], a["iso"]["sigma_F0"], rtol=1e-12)
        np.testing.assert_allclose(b["iso"]["sigma_H0"], a["iso"]["sigma_H0"], rtol=1e-12)
        root = f["K_A"] * f["K_v"] * f["K_Fbeta"] * f["K_Falpha"]
        np.testing.assert_allclose(
            b["iso"]["sigma_F"], np.multiply(b["iso"]["sigma_F0"], root), rtol=1e-12
        )


def test_reliability_of_999_percent_divides_agma_bending_factors_by_125(default):
    # AGMA 2001 Table 8 (Shigley Table 14-10): K_R = 1.00 at 99 %, 1.25 at 99.9 %.
    assert default["meshes"][0]["agma"]["factors"]["reliability_percent"] == 99.0
    surer = rated("--reliability-percent", "99.9")
    for a, b in zip(default["meshes"], surer["meshes"], strict=True):
        assert b["agma"]["factors"]["reliability_percent"] == 99.9
        np.testing.assert_allclose(b["agma"]["S_F"], np.divide(a["agma"]["S_F"], 1.25), rtol=3e-3)


@pytest.mark.parametrize(
    ("option", "value", "named"),
    [
        # a fraction, the unit `rate --reliability` took before: named with its percent
        ("--reliability-percent", "0.999", "a fraction: 99.9 % is --reliability-percent 99.9"),
        ("--reliability-percent", "50", "50 < R ≤ 99.99 %"),  # K_R's range is open at 50 %
        ("--reliability-percent", "100", "50 < R ≤ 99.99 %"),
        ("--reliability-percent", "nan", "50 < R ≤ 99.99 %"),
        # the former spelling, a fraction here and a percent in `pinwind life`: refused
        ("--reliability", "0.999", "give --reliability-percent R (--reliability-percent 99.9)"),
        ("--reliability", "99", "in percent, as pinwind life does"),
    ],
)
def test_a_reliability_outside_agma_s_range_or_as_a_fraction_is_refused(option, value, named):
    # One line on stderr with the value and the accepted range, exit 2, before any run.
    out = run_cli(*RATED, option, value)
    assert out.returncode == 2, out.stderr
    (line,) = out.stderr.strip().splitlines()
    assert f"{option} {value}" in line and named in line, line
    assert "50 < R ≤ 99.99" in line, line


def test_iso_geometry_factor_gives_j_of_one_over_form_times_stress_correction():
    # ISO 6336-3's root stress is F_t/(b m) Y_F Y_S, AGMA's F_t/(b m J): the same for
    # J = 1/(Y_F Y_S).
    for mesh in rated("--geometry-factor", "iso")["meshes"]:
        iso = mesh["iso"]["factors"]
        expected = 1.0 / (np.array(iso["Y_F"]) * np.array(iso["Y_S"]))
        np.testing.assert_allclose(mesh["agma"]["factors"]["J"], expected, rtol=1e-12)


def test_accuracy_and_quality_options_reach_every_mesh():
    data = rated("--accuracy-grade", "8", "--quality", "7")
    for mesh in data["meshes"]:
        assert mesh["iso"]["factors"]["accuracy_grade"] == 8
        assert mesh["agma"]["factors"]["quality"] == 7


def test_table_caption_names_the_factors_given():
    out = CliRunner().invoke(
        app, [*RATED, "--application-factor", "1.25", "--geometry-factor", "iso", "--quality", "8"]
    )
    assert out.exit_code == 0, out.output
    text = " ".join(out.stdout.split())
    for named in ("K_A = 1.25", "K_o = 1.25", "Q_v = 8", "J = 1/(Y_F Y_S) of ISO 6336-3"):
        assert named in text, named
    assert "AGMA 908-B89" not in text


@pytest.mark.parametrize("value", ["0", "-1", "nan", "inf", "0.99", "1e-30"])
def test_an_application_factor_below_1_or_not_finite_is_refused(value):
    # K_A scales the run's forces up by the overloads they do not hold: below 1 it would rate
    # the gears for less than the loads the run computed
    out = CliRunner().invoke(app, [*RATED, "--application-factor", value])
    assert isinstance(out.exception, InputError)  # ``pinwind`` prints it on one line, exit 2
    assert "--application-factor" in str(out.exception) and ">= 1" in str(out.exception)
