"""The torsional modes of a multi-stage gearbox are those of its joint-angle M and K by hand.

``benchmarks/independent_modes.py`` recodes the natural modes of the NREL 5 MW gearbox and the
Saleh 2017 drivetrain with ideal bearings from the model files alone (docs/validation.md,
"Independent recoding of the natural modes"): M from the links' masses and inertias in the
joints' angles (a planet's m r_c² and its own inertia on its carrier's angle), K from the
torsional springs and each mesh's ISO 6336-1 c_γα b along its line of action, the planet meshes'
rows Lin & Parker's (1999) torsional deflections; and with radial bearings, their planar model.
Here the Saleh drivetrain (two parallel stages behind a planetary stage, seven joints, and on
radial bearings 21 coordinates) and the NREL 5 MW gearbox with its generator held.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import pinwind
from tests.benchmarks import benchmark_module

recoding = benchmark_module("independent_modes.py", "independent_modes")


def test_a_planet_mesh_s_row_turns_the_carrier_by_the_line_s_arm_about_the_carrier_axis(tmp_path):
    r = recoding
    model = r.ideal_copy(r.NREL, tmp_path / "nrel.urdf")
    t = r.torsional_model(model)
    planets = {1: ("lss", "iss", "stage1_ring"), 2: ("iss", "ims", "stage2_ring")}
    for stage, (carrier, sun, ring) in planets.items():
        assert r.lin_parker_check(model, t, carrier, sun, r.planets(stage), {ring}) < 1e-12


def test_the_saleh_drivetrain_s_torsional_modes_are_those_of_its_joint_angle_m_and_k(tmp_path):
    r = recoding
    model = r.ideal_copy(r.SALEH, tmp_path / "saleh.urdf")
    t = r.torsional_model(model)
    recoded = t.frequencies_hz()
    pinwind_hz, _ = r.pinwind_modes(model)
    assert len(pinwind_hz) == len(recoded) == 7
    assert pinwind_hz[0] == 0.0 and recoded[0] < 1e-6 * recoded[-1]  # the train turning
    np.testing.assert_allclose(pinwind_hz[1:], recoded[1:], rtol=1e-12)
    # The planet modes (sun, carrier and the other stages still): a planet on its two meshes,
    # I_p ω² = (k_sp + k_rp) r_b,p², twice (N − 1 = 2 for three planets).
    k = t.k_mean
    rbp = 0.015 * 48 * math.cos(math.radians(24.5)) / 2
    planet = math.sqrt((k["sun_planet1"] + k["planet1_ring"]) * rbp**2 / 77.78) / (2 * math.pi)
    assert np.sum(np.isclose(pinwind_hz, planet, rtol=1e-12)) == 2


def test_the_nrel_5mw_gearbox_s_torsional_modes_with_the_generator_held(tmp_path):
    r = recoding
    model = r.ideal_copy(r.NREL, tmp_path / "nrel.urdf")
    recoded = r.torsional_model(model).frequencies_hz(hold=("generator",))
    pinwind_hz, _ = r.pinwind_modes(model, "--hold", "generator")
    assert len(pinwind_hz) == len(recoded) == 11
    # The rotor on the train (0.63 Hz) sits 2200 times below the highest mode: eigh resolves its
    # ω² to about ε (f_max/f_1)² = 1e-9 of it (the benchmark's flexibility form puts pinwind
    # and the recoding within 6e-10 of the exact value); the others to rounding.
    np.testing.assert_allclose(pinwind_hz[0], recoded[0], rtol=3e-9)
    np.testing.assert_allclose(pinwind_hz[1:], recoded[1:], rtol=1e-12)


def test_the_saleh_drivetrain_s_planar_modes_on_radial_bearings_are_those_of_its_m_and_k(tmp_path):
    # Every shaft and planet translating in a radial bearing (two slides each): each mesh's row
    # gains the line of action's direction on its gears' slides, which depends on the flank
    # (Lin & Parker 1999's planar model). Flipping one mesh's flank moves a mode by up to 12 %.
    r = recoding
    model = r.planar_copy(r.SALEH, tmp_path / "saleh_planar.urdf", r.SALEH_RADIAL)
    pinwind_hz, err = r.pinwind_modes(model)
    flank = r.unloaded_flanks(err, model)
    assert len(flank) == 8
    recoded = r.torsional_model(model, flank=flank).frequencies_hz()
    assert len(pinwind_hz) == len(recoded) == 7 + 2 * 7
    np.testing.assert_allclose(pinwind_hz[1:], recoded[1:], rtol=1e-12)
    other = r.torsional_model(model, flank={**flank, "stage1": -flank["stage1"]})
    assert np.max(np.abs(other.frequencies_hz()[1:] / pinwind_hz[1:] - 1)) > 1e-3


def test_the_shipped_nrel_5mw_gearbox_s_modes_are_those_of_its_rows_by_hand(tmp_path):
    # Every row's five springs at its position, the shafts' and planets' axial and tilt slides,
    # K_y ≠ K_z, the full inertia tensors: the recoding's M and K give pinwind's 62 modes, with
    # stage 3's helical mesh row along the tooth force's direction f = n − s tan β_b k (its
    # axial thrust pushing and tilting the shafts). Leaving the thrust out of the recoded row
    # moves the modes by up to 4 %: pinwind's row has it.
    r = recoding
    pinwind_hz, err = r.pinwind_modes(r.NREL)
    flank = r.unloaded_flanks(err, r.NREL)
    mine = r.spatial_model(r.NREL, flank).frequencies_hz()
    assert len(pinwind_hz) == len(mine) == 62
    np.testing.assert_allclose(pinwind_hz[1:], mine[1:], rtol=1e-9)
    without = r.spatial_model(r.NREL, flank, thrust=0.0).frequencies_hz()
    assert np.max(np.abs(without[1:] / pinwind_hz[1:] - 1)) > 1e-2


def test_a_helical_mesh_s_thrust_is_carried_by_its_shafts_bearing_rows():
    # Stage 3 (β = 10°) at rated: the tooth force has an axial part F_bt tan β_b (the mesh's
    # `axial` series), which the high-speed shaft's rows must carry in their axial springs
    # (docs/model_format.md: the rows add up to the bearing's reaction).
    gb = pinwind.load(recoding.NREL)
    torque = 3.94599e6
    res = pinwind.simulate(
        gb,
        duration=0.004,
        dt=2e-5,
        torques={"rotor": torque, "generator": torque / 96.3542},
        initial_speeds={"rotor": 1.267, "lss": 1.267},
        meshes={"all": "compliant"},
    )
    thrust = float(np.mean(res.mesh("stage3").axial))
    assert thrust > 1e4
    rows = sum(np.asarray(res.row(n).force) for n in res.row_names if n.startswith("hss."))
    reaction = np.asarray(res.bearing("hss").force_local)
    assert abs(float(np.mean(reaction[:, 2]))) == pytest.approx(thrust, rel=0.05)
    assert abs(float(np.mean(rows[:, 2]))) == pytest.approx(thrust, rel=0.05)
