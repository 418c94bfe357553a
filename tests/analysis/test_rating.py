"""Rating a run: the mesh forces of a simulation turned into ISO and AGMA safety factors."""

import json
import math
import subprocess
import sys

import pytest

import pinwind
from pinwind.analysis.rating import rate
from pinwind.gears.gear_pair import GearPair
from pinwind.gears.rating_agma import agma_rating
from tests.conftest import MODELS

TORQUES = {"carrier": 1e6, "sun": -1e6 / 6}


@pytest.fixture(scope="module")
def saleh():
    gb = pinwind.load(MODELS / "saleh2017_planetary.urdf")
    res = pinwind.simulate(gb, duration=0.01, dt=1e-3, torques=TORQUES)
    return gb, res


def test_rated_tangential_force_is_the_sun_torque_over_three_sun_radii(saleh):
    gb, res = saleh
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
    assert rating.gears["sun"].S_H_agma == pytest.approx(min(sun.agma.S_H), rel=1e-12)


def test_unloaded_mesh_cannot_be_rated(saleh):
    gb, _ = saleh
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
