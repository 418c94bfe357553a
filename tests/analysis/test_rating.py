"""Rating a run: the mesh forces of a simulation turned into ISO and AGMA safety factors."""

import json
import math
import re
import subprocess
import sys
import warnings

import pytest
from numpy.testing import assert_allclose

import pinwind
from pinwind.analysis.rating import rate, rate_pair
from pinwind.errors import (
    InvalidGearTrain,
    PinwindWarning,
    PointedTeeth,
    RatingAtZeroSpeed,
    RatingOfTransient,
    StepTooCoarse,
    TorquesUnbalanced,
    UndercutGear,
)
from pinwind.gears.gear_pair import GearPair
from pinwind.gears.rating_agma import agma_rating
from tests.conftest import MODELS, two_gear_urdf

TORQUES = {"carrier": 1e6, "sun": -1e6 / 6}


@pytest.fixture(scope="module")
def saleh():
    gb = pinwind.load(MODELS / "saleh2017_planetary.urdf")
    res = pinwind.simulate(gb, duration=0.01, dt=1e-3, torques=TORQUES)
    return gb, res


def test_rated_tangential_force_is_the_sun_torque_over_three_sun_radii(saleh):
    gb, res = saleh
    with pytest.warns(RatingAtZeroSpeed):  # balanced torques, no speed: the run stands still
        rating = rate(gb, res)
    f_t = (1e6 / 6) / (3 * 0.18)  # 308.6 kN per sun–planet mesh
    for m in rating.meshes:
        assert m.load.tangential_force == pytest.approx(f_t, rel=1e-9)
    sun = [m for m in rating.meshes if m.mesh.startswith("sun")][0]
    assert sun.pair.names == ("sun", "planet1")
    # The same pair rated directly at F_t gives the same AGMA stresses.
    pair = GearPair(24, 48, module=0.015, pressure_angle=math.radians(24.5), face_width=0.38)
    direct = agma_rating(pair, sun.load)
    assert sun.agma.bending_stress == pytest.approx(direct.bending_stress, rel=1e-12)
    assert set(rating.gears) == {"sun", "planet1", "planet2", "planet3", "ring"}
    # A gear's factor is the smallest over its meshes (the three sun meshes carry equal loads
    # only up to the rounding of the planets' share).
    sun_meshes = [m for m in rating.meshes if m.mesh.startswith("sun")]
    smallest = min(min(m.agma.S_H) for m in sun_meshes)
    assert rating.gears["sun"].S_H_agma == pytest.approx(smallest, rel=1e-12)


def test_unloaded_mesh_cannot_be_rated(saleh):
    gb, _ = saleh
    with pytest.warns(StepTooCoarse):
        idle = pinwind.simulate(gb, duration=0.002, dt=1e-3, torques={})
    with pytest.raises(pinwind.PinwindError, match="carries no load|needs a loaded mesh"):
        rate(gb, idle)


def test_rate_command_prints_json_with_safety_factors_per_mesh_and_gear(tmp_path):
    out = subprocess.run(
        [sys.executable, "-m", "pinwind", "rate", str(MODELS / "saleh2017_planetary.urdf"),
         "--torque", "carrier=1e6", "--torque", "sun=-166666.6666666667", "--duration",
         "0.01", "--json", "--material", "all=42CrMo4"],
        capture_output=True, text=True, timeout=120, cwd=tmp_path,
    )  # fmt: skip
    assert out.returncode == 0, out.stderr
    data = json.loads(out.stdout)
    assert len(data["meshes"]) == 6
    first = data["meshes"][0]
    assert first["mesh"] == "sun_planet1"
    assert first["agma"]["S_H"][0] > 0 and first["iso"]["S_F"][0] > 0
    assert data["gears"]["ring"]["S_H_iso"] > data["gears"]["sun"]["S_H_iso"]
    # Through-hardened 42CrMo4 (σ_Hlim 770 MPa) cannot carry 1 MN·m on this stage in pitting.
    assert data["passes"] is False


def test_rate_command_refuses_a_joint_both_driven_and_given_a_start_speed(tmp_path):
    out = subprocess.run(
        [sys.executable, "-m", "pinwind", "rate", str(MODELS / "saleh2017_planetary.urdf"),
         "--speed", "carrier=14.2", "--initial-speed", "carrier=10", "--duration", "0.01"],
        capture_output=True, text=True, timeout=120, cwd=tmp_path,
    )  # fmt: skip
    assert out.returncode == 2
    assert "--speed" in out.stderr and "--initial-speed" in out.stderr and "carrier" in out.stderr


# --- implausible runs and gears (issue 25 item 6) -----------------------------------------------

#: Saleh's carrier at its rated 14.2 rpm [rad/s].
CARRIER_SPEED = 14.2 * 2 * math.pi / 60


def test_rating_an_accelerating_run_warns_with_the_net_torque_at_the_carrier(saleh):
    gb, _ = saleh
    with pytest.warns(TorquesUnbalanced, match=r"leave 1e\+06 N·m that nothing holds"):
        unbalanced = pinwind.simulate(
            gb, duration=0.01, dt=1e-3, torques={"carrier": 1e6},
            initial_speeds={"carrier": CARRIER_SPEED},
        )  # fmt: skip
    with pytest.warns(RatingOfTransient, match=r'leave 1e\+06 N·m at joint "carrier"'):
        rate(gb, unbalanced)


def test_rating_a_steady_run_at_speed_warns_nothing(saleh):
    gb, _ = saleh
    steady = pinwind.simulate(
        gb, duration=0.01, dt=1e-3, torques=TORQUES, initial_speeds={"carrier": CARRIER_SPEED}
    )
    with warnings.catch_warnings():
        warnings.simplefilter("error", PinwindWarning)
        rate(gb, steady)


def test_rating_a_run_at_standstill_warns_that_the_dynamic_factors_are_static(saleh):
    gb, res = saleh  # balanced torques, no initial speed: every joint stands still
    with pytest.warns(RatingAtZeroSpeed, match="pitch-line speed is below 1 µm/s"):
        rating = rate(gb, res)
    for m in rating.meshes:
        assert_allclose([m.iso.factors.K_v, m.agma.factors.K_v], 1.0, rtol=1e-6)


def test_rating_an_undercut_pinion_warns_with_the_undercut_limit():
    # 15 teeth at 20°: x_min = 1 − 15 sin²20° / 2 = 0.1227 (DIN 3960, ISO 53 profile A tool)
    pair = GearPair(15, 30, module=0.003, pressure_angle=math.radians(20.0), face_width=0.02)
    x_min = 1.0 - 15 * math.sin(math.radians(20.0)) ** 2 / 2.0
    with pytest.warns(UndercutGear, match=re.escape(f"unless x ≥ {x_min:+.3f}")):
        rate_pair(pair, 1000.0, pitch_line_speed=5.0)


def test_rating_pointed_teeth_is_refused_naming_the_gear():
    # 12 teeth with x = 0.9: the flanks cross below the tip circle (s_at < 0)
    pair = GearPair(
        12, 60, module=0.003, pressure_angle=math.radians(20.0), face_width=0.02,
        profile_shift_1=0.9, names=("pinion", "wheel"),
    )  # fmt: skip
    with pytest.raises(PointedTeeth, match=r"pinion \(12 teeth, x = \+0.900\).*pointed teeth"):
        rate_pair(pair, 1000.0, pitch_line_speed=5.0)


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"face_width": math.nan}, "pinion–wheel: the face width is nan"),
        ({"pressure_angle": 0.0}, "pinion–wheel: the pressure angle is 0°"),
    ],
)
def test_a_pair_with_a_nan_face_width_or_no_pressure_angle_is_refused(change, message):
    values = {"module": 0.003, "pressure_angle": math.radians(20.0), "face_width": 0.02} | change
    with pytest.raises(InvalidGearTrain, match=message):
        GearPair(20, 40, **values)


def test_sweep_with_a_zero_pressure_angle_is_refused_before_any_row(tmp_path):
    out = subprocess.run(
        [sys.executable, "-m", "pinwind", "sweep", "planetary", "--center-distance", "540",
         "--module", "15", "--ratio", "6:6.4", "--pressure-angle", "0", "-o",
         str(tmp_path / "designs.csv"), "--workers", "1"],
        capture_output=True, text=True, timeout=120, cwd=tmp_path,
    )  # fmt: skip
    assert out.returncode == 2, out.stderr
    assert out.stderr.count("\n") == 1 and "--pressure-angle is 0°" in out.stderr
    assert not (tmp_path / "designs.csv").exists()


def test_rate_command_warns_of_an_unbalanced_run_in_one_line_each(tmp_path):
    out = subprocess.run(
        [sys.executable, "-m", "pinwind", "rate", str(MODELS / "saleh2017_planetary.urdf"),
         "--torque", "carrier=1e6", "--initial-speed", "carrier=14.2", "--duration", "0.01",
         "--json"],
        capture_output=True, text=True, timeout=120, cwd=tmp_path,
    )  # fmt: skip
    assert out.returncode == 0, out.stderr
    lines = out.stderr.splitlines()
    assert len(lines) == 2 and all(line.startswith("warning: ") for line in lines)
    assert "do not balance through the gear train" in lines[0]
    assert "the train accelerates at t = 0.01 s" in lines[1]


def test_rate_command_refuses_a_model_with_pointed_teeth_in_one_line(tmp_path):
    # g1: 12 teeth with x = 0.9 on a 12/60 pair of module 2 mm, at the centre distance of its
    # shifts (pinwind refuses the model otherwise); its flanks cross below the tip.
    text = two_gear_urdf(teeth=("12", "60"), centre_distance=0.0736651).replace(
        'face_width_mm="20" internal="false"/>', 'face_width_mm="20" internal="false" '
        'profile_shift="0.9"/>', 1,
    )  # fmt: skip
    model = tmp_path / "pointed.urdf"
    model.write_text(text, encoding="utf-8")
    out = subprocess.run(
        [sys.executable, "-m", "pinwind", "rate", str(model), "--torque", "a=10", "--torque",
         "b=-50", "--initial-speed", "a=100"],
        capture_output=True, text=True, timeout=120, cwd=tmp_path,
    )  # fmt: skip
    assert out.returncode == 2, out.stderr
    errors = [line for line in out.stderr.splitlines() if line.startswith("error: ")]
    assert len(errors) == 1 and "Traceback" not in out.stderr
    assert "g1 (12 teeth, x = +0.900)" in errors[0] and "pointed teeth" in errors[0]


def test_rating_a_run_started_at_rest_under_torques_balanced_to_seven_digits_warns(saleh):
    # docs/rating.md's command: T_sun = -166666.7 N·m against T_carrier/6 = 166666.67 N·m
    # leaves 0.2 N·m at the sun, 6 × 0.2 = 1.2 N·m at the carrier: the train creeps from rest
    # to µm/s in 0.05 s, still a rating at standstill (dynamic factors 1).
    gb, _ = saleh
    creeping = pinwind.simulate(
        gb, duration=0.05, dt=1e-3, torques={"carrier": 1e6, "sun": -166666.7}
    )
    with pytest.warns(RatingAtZeroSpeed, match="pitch-line speed is below 10 µm/s"):
        rating = rate(gb, creeping)
    speed = max(m.load.pitch_line_speed for m in rating.meshes)
    assert 1e-6 < speed < 1e-5
    # AGMA 2001 at Q_v = 10 (Shigley eq. 14-27): K_v = ((A + √V)/A)^B, V in ft/min
    # (196.85 v, v in m/s; Shigley's SI form rounds it to 200), B = 0.25 (12 − Q_v)^(2/3),
    # A = 50 + 56 (1 − B): 1 + 1.6e-4 at 5 µm/s.
    b = 0.25 * (12 - 10) ** (2 / 3)
    a = 50 + 56 * (1 - b)
    for m in rating.meshes:
        feet_per_minute = m.load.pitch_line_speed * 60 / 0.3048
        assert_allclose(m.agma.factors.K_v, ((a + math.sqrt(feet_per_minute)) / a) ** b, rtol=1e-12)
        assert_allclose([m.iso.factors.K_v, m.agma.factors.K_v], 1.0, rtol=3e-4)


def test_dynamic_factors_take_the_pitch_line_speed_relative_to_the_carrier(saleh):
    # ISO 6336-1's K_v of a planetary stage takes v in the carrier's frame (KISSsoft's ISO 6336
    # report of the NREL 5 MW stage 1: v = π d_sun (n_sun − n_carrier)/60, "(Planet)"). With the
    # ring fixed the sun turns ω_s = ω_c (1 + z_r/z_s), so relative to the carrier
    # ω_s − ω_c = ω_c z_r/z_s and v = r_s ω_c z_r/z_s = m z_r ω_c/2 for every mesh of the stage
    # (24/48/120 teeth, m = 15 mm): 0.9 m × 1.4870 rad/s = 1.3383 m/s, 5/6 of the sun's
    # absolute r_s ω_s = 1.6060 m/s.
    gb, _ = saleh
    steady = pinwind.simulate(
        gb, duration=0.01, dt=1e-3, torques=TORQUES, initial_speeds={"carrier": CARRIER_SPEED}
    )
    rating = rate(gb, steady)
    v = 0.015 * 120 / 2 * CARRIER_SPEED
    f_t = (1e6 / 6) / (3 * 0.18)  # N per mesh, the sun torque over three sun radii
    specific = f_t / 380.0  # F_t/b [N/mm], K_A = 1
    k1, k2 = 14.9, 0.0193  # ISO 6336-1 method C, spur, ISO 1328 grade 6
    b = 0.25 * (12 - 10) ** (2 / 3)  # AGMA 2001 (Shigley eq. 14-27), Q_v = 10
    a = 50 + 56 * (1 - b)
    agma_k_v = ((a + math.sqrt(v * 60 / 0.3048)) / a) ** b
    for m in rating.meshes:
        assert m.load.pitch_line_speed == pytest.approx(v, rel=1e-9), m.mesh
        # z1, u of the pair (pinion first): sun 24 / planet 48; planet 48 / ring −120
        z1, u = (24, 2.0) if m.mesh.startswith("sun") else (48, -2.5)
        iso_k_v = 1 + (k1 / specific + k2) * z1 * v / 100 * math.sqrt(u * u / (1 + u * u))
        assert m.iso.factors.K_v == pytest.approx(iso_k_v, rel=1e-9), m.mesh
        assert m.agma.factors.K_v == pytest.approx(agma_k_v, rel=1e-9), m.mesh
