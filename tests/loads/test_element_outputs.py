"""Generator and rotor torques as outputs of their own: Result, summary, export and log."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

import pinwind
from pinwind.analysis.summary import summary_tables
from pinwind.errors import TorquesUnbalanced, UnknownElement
from pinwind.io.export import columns
from pinwind.loads.generator import ConstantTorque
from pinwind.loads.rotor import HeierCp, Rotor
from pinwind.model.gearbox import loads

RPM = 2 * math.pi / 60


def heier(tsr):
    """Heier's C_p(λ) at β = 0, written out here."""
    inv = 1 / tsr - 0.035
    return 0.5176 * (116 * inv - 5) * np.exp(-21 * inv) + 0.0068 * tsr


@pytest.fixture
def pair(pair_urdf):
    return loads(pair_urdf(), path="pair.urdf")  # 20/40: b turns at −½ a


def test_constant_generator_torque_is_its_own_output_and_part_of_the_joint_torque(pair):
    with pytest.warns(TorquesUnbalanced):
        res = pinwind.simulate(pair, duration=0.05, dt=1e-3, torques={"a": 30.0},
                               generators={"b": ConstantTorque(45.0)})  # fmt: skip
    assert res.generator_names == ["b"]
    assert_allclose(res.generator("b").torque, 45.0, rtol=0, atol=0)
    # The shaft feels −T_gen: with nothing else on b, that is its whole joint torque.
    assert_allclose(res.joint("b").torque, -45.0, rtol=0, atol=0)
    assert res.rotor_names == [] and res.rotor_torque.shape == (len(res), 0)
    with pytest.raises(UnknownElement):
        res.generator("a")


def test_rotor_held_at_speed_gives_power_over_speed_from_cp(pair):
    radius, rho, wind, scale = 40.0, 1.2, 9.0, 1.03
    speed = 1.7  # rad/s on a: λ = 7.56
    rotor = Rotor(radius=radius, air_density=rho, cp=HeierCp(scale=scale))
    res = pinwind.simulate(pair, duration=0.05, dt=1e-3, speeds={"a": speed},
                           rotors={"a": rotor}, wind=wind)  # fmt: skip
    tsr = speed * radius / wind
    cp = scale * heier(tsr)
    power = 0.5 * rho * math.pi * radius**2 * wind**3 * cp
    r = res.rotor("a")
    assert_allclose(r.torque, power / speed, rtol=1e-12)
    assert_allclose(r.power, power, rtol=1e-12)
    assert_allclose(r.tip_speed_ratio, tsr, rtol=1e-12)
    assert_allclose(r.power_coefficient, cp, rtol=1e-12)
    assert_allclose(r.wind_speed, wind, rtol=0)
    # The driver holds the unloaded pair against it: the joint's torque (rotor + driver) is 0.
    assert np.abs(res.joint("a").torque).max() < 1e-9 * r.torque.max()
    table = summary_tables(res, plain=True)[-1]
    assert str(table.title).startswith("Rotors") and "a" in table.columns[0]._cells


def test_element_outputs_go_to_the_log_and_the_export_columns(pair, tmp_path):
    rotor = Rotor(radius=40.0)
    path = tmp_path / "run.mcap"
    res = pinwind.simulate(pair, duration=0.02, dt=1e-3, speeds={"a": 1.5}, rotors={"a": rotor},
                           wind=10.0, generators={"b": ConstantTorque(7.0)},
                           log=path, progress=False)  # fmt: skip
    back = pinwind.read_log(path)
    assert back.generator_names == ["b"] and back.rotor_names == ["a"]
    for name in ("generator_torque", "rotor_torque", "rotor_power", "rotor_wind_speed"):
        assert np.array_equal(getattr(back, name), getattr(res, name)), name
    names = dict(columns(back))
    assert_allclose(names["generator/b/torque_N_m"], 7.0, rtol=0)
    assert_allclose(names["rotor/a/power_W"], res.rotor("a").power, rtol=0)
    assert "rotor/a/tip_speed_ratio" in names and "rotor/a/wind_speed_m_s" in names
