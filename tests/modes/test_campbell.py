"""The Campbell diagram (``modes/campbell.py``): mesh lines z·Ω/2π and their crossings.

For the 20/40 pair of ``tests/conftest.two_gear_urdf`` driven at Ω on gear A (fixed axes), the
mesh frequency is z_A Ω / 2π exactly, its harmonic h that times h, and the line meets a mode f_n
at Ω* = 2π f_n / (h z_A).

For the spinning rotor of ``tests/modes/test_gyroscopic_modes.py`` (J_p < J_t), the tilt modes
split with the spin Ω into ω_f,b(Ω) = (± J_p Ω + √((J_p Ω)² + 4 J_t k_t)) / (2 J_t), and the 1×
line (the rotor's shaft order, ω = Ω) meets them where J_t Ω² ∓ J_p Ω² − k_t = 0:
Ω_f = √(k_t / (J_t − J_p)) (forward whirl) and Ω_b = √(k_t / (J_t + J_p)) (backward whirl).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from pinwind.errors import InputError, SpeedOutOfRange
from pinwind.model.compliance import MeshCompliance
from pinwind.model.gearbox import loads
from pinwind.modes.campbell import campbell
from tests.conftest import two_gear_urdf
from tests.dynamics.test_time_stepping import K_MESH, K_SINGLE, MASS
from tests.modes.test_gyroscopic_modes import ROTORS, TILT, rotor, whirl_frequencies

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


def test_a_spinning_rotor_s_campbell_diagram_splits_and_meets_the_1x_line_where_omega_f_is_omega():
    polar, transverse = ROTORS[0]
    top = 400.0  # rad/s, beyond both crossings
    diagram = campbell(rotor(polar, transverse), "rotor", (0.0, top), points=41)
    # The split: the tilt curves at each sampled speed are the closed form's two branches.
    split = diagram.frequencies[:, :2] * 2 * math.pi
    expected = np.array(
        [sorted(whirl_frequencies(polar, transverse, x)) for x in diagram.speed_grid]
    )
    np.testing.assert_allclose(split, expected, rtol=1e-6)
    one = [c for c in diagram.crossings if c.excitation.label == "shaft rotor"]
    by_whirl = {c.whirl: c.speed for c in one}
    np.testing.assert_allclose(
        by_whirl["forward"], math.sqrt(TILT / (transverse - polar)), rtol=1e-9
    )
    np.testing.assert_allclose(
        by_whirl["backward"], math.sqrt(TILT / (transverse + polar)), rtol=1e-9
    )
    for c in one:  # on the 1× line: the mode's frequency is the speed
        np.testing.assert_allclose(c.frequency * 2 * math.pi, c.speed, rtol=1e-9)
    # No line for the bearing's slides: they do not turn.
    assert {e.label for e in diagram.excitations} == {"shaft rotor"}
