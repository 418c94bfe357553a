"""modes_in_spectrum: a train let go rings at its natural frequencies; a wrong one is caught."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from pinwind.dynamics.compliant import mesh_setup
from pinwind.errors import CheckFailed
from pinwind.model.gearbox import loads
from pinwind.testing import free_vibration, modes_in_spectrum
from pinwind.testing.free_vibration import chosen_modes
from tests.dynamics.test_compliant_bearing import disc_urdf
from tests.dynamics.test_flank_contact import ALPHA, MODULE, Z1, Z2, pair_urdf

PAIR = pair_urdf(bearing="", mesh='stiffness_variation="constant" damping_ratio="0.02"')
#: The pair's axial inertias [kg·m²] (pair_urdf) and base radii [m].
J1, J2 = 0.01, 0.16
RB1, RB2 = MODULE * Z1 / 2 * math.cos(ALPHA), MODULE * Z2 / 2 * math.cos(ALPHA)


def test_a_compliant_pair_rings_at_the_two_inertia_frequency_of_its_mesh():
    """ω² = k (r_b1²/J1 + r_b2²/J2), k the mean mesh stiffness c_γα b."""
    gb = loads(PAIR)
    k = mesh_setup(gb, gb.meshes, driver_index=[], dt=None).compliant[0].stiffness
    (mode,) = chosen_modes(gb)
    omega = math.sqrt(k * (RB1**2 / J1 + RB2**2 / J2))
    np.testing.assert_allclose(mode.frequency, omega / (2 * math.pi), rtol=1e-9)
    figure = modes_in_spectrum(gb, rtol=0.01)
    # the step's own frequency error, (ω dt)²/12 = rtol/10 at the default dt, and no more
    assert figure.measured < 0.2 * 0.01


def test_a_disc_in_radial_axial_and_tilt_springs_rings_at_each_of_its_five_modes():
    gb = loads(disc_urdf('radial_stiffness="1e6" axial_stiffness="3e6" tilt_stiffness="2e4"'))
    figure = modes_in_spectrum(gb, rtol=0.01)
    assert "5 modes" in figure.detail


def test_modes_three_percent_too_high_are_caught_with_the_peak_they_miss(monkeypatch):
    gb = loads(PAIR)
    real = free_vibration.linearise

    def stiffer(*args, **kwargs):
        lin = real(*args, **kwargs)
        return replace(lin, stiffness=lin.stiffness * 1.03**2)

    monkeypatch.setattr(free_vibration, "linearise", stiffer)
    with pytest.raises(CheckFailed) as caught:
        modes_in_spectrum(gb, rtol=0.01)
    np.testing.assert_allclose(caught.value.measured, 1 - 1 / 1.03, atol=0.003)
    assert 'in the speed of "a"' in caught.value.detail
