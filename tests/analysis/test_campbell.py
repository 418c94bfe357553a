"""The Campbell diagram (``analysis/campbell.py``): mesh lines z·Ω/2π and their crossings.

For the 20/40 pair of ``tests/conftest.two_gear_urdf`` driven at Ω on gear A (fixed axes), the
mesh frequency is z_A Ω / 2π exactly, its harmonic h that times h, and the line meets a mode f_n
at Ω* = 2π f_n / (h z_A).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from pinwind.analysis.campbell import campbell
from pinwind.errors import InputError, SpeedOutOfRange
from pinwind.model.compliance import MeshCompliance
from pinwind.model.gearbox import loads
from tests.conftest import two_gear_urdf
from tests.dynamics.test_time_stepping import K_MESH, K_SINGLE, MASS

Z_A = 20
F_N = math.sqrt(K_MESH / MASS) / (2 * math.pi)


def _diagram(low: float, high: float):
    gb = loads(two_gear_urdf(), "pair.urdf")
    compliance = MeshCompliance(stiffness=K_SINGLE, variation="constant", damping=0.0)
    return campbell(gb, "a", (low, high), meshes={"m": compliance}, harmonics=2)


def test_mesh_lines_are_teeth_times_speed_and_cross_the_mode_where_they_meet_it():
    top = 2 * math.pi * F_N / Z_A * 1.5  # the fundamental's crossing inside the range
    diagram = _diagram(0.0, top)
    mesh = {e.harmonic: e for e in diagram.excitations if e.label.startswith("mesh")}
    np.testing.assert_allclose(mesh[1].per_speed, Z_A / (2 * math.pi), rtol=1e-12)
    np.testing.assert_allclose(mesh[2].per_speed, 2 * Z_A / (2 * math.pi), rtol=1e-12)
    found = {
        c.excitation.harmonic: c.speed for c in diagram.crossings if c.excitation in mesh.values()
    }
    for h in (1, 2):
        np.testing.assert_allclose(found[h], 2 * math.pi * F_N / (h * Z_A), rtol=1e-12)


def test_a_range_below_every_crossing_lists_none():
    diagram = _diagram(0.0, 0.5 * 2 * math.pi * F_N / (2 * Z_A))
    assert [c for c in diagram.crossings if c.excitation.label.startswith("mesh")] == []


def test_an_empty_speed_range_is_refused():
    with pytest.raises(InputError, match="0 ≤ lowest < highest"):
        _diagram(10.0, 5.0)


def test_a_range_beyond_the_speed_a_gear_can_turn_at_is_refused():
    with pytest.raises(SpeedOutOfRange, match="beyond the 1e\\+05 rad/s"):
        _diagram(0.0, 2e5)
