"""A compliant mesh's mean stiffness c_γα·b given directly (``<mesh mean_stiffness>``, issue 36).

ISO 6336-1 relates the mean mesh stiffness to the single-pair one, c_γα = c′ (0.75 ε_α + 0.25).
Given the mean, the single-pair stiffness is the relation taken backwards, so that the constant
stiffness and the mean over a base pitch of the ``path`` variation are the value given. The pair
of ``tests/conftest.two_gear_urdf`` (20/40 teeth, module 2 mm, 20°, standard addenda, at its
reference centre distance) has, by hand,

    ε_α = [√(r_a1² − r_b1²) + √(r_a2² − r_b2²) − a sin α] / (π m cos α)

and its mesh mode, the gears' inertias J_A = 0.0015 and J_B = 0.006 kg·m² on the line of action
at their base radii, ω² = k (r_b1²/J_A + r_b2²/J_B).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from pinwind.dynamics.compliant import (
    mean_mesh_stiffness,
    mesh_choices,
    mesh_setup,
    pair_table,
    single_pair,
)
from pinwind.errors import MalformedModel
from pinwind.model.gearbox import loads
from pinwind.modes.linearisation import linearise
from tests.conftest import two_gear_urdf

MODULE, ALPHA, Z1, Z2 = 0.002, math.radians(20.0), 20, 40
R1, R2 = MODULE * Z1 / 2, MODULE * Z2 / 2
RB1, RB2 = R1 * math.cos(ALPHA), R2 * math.cos(ALPHA)
CONTACT_RATIO = (
    math.sqrt((R1 + MODULE) ** 2 - RB1**2)
    + math.sqrt((R2 + MODULE) ** 2 - RB2**2)
    - (R1 + R2) * math.sin(ALPHA)
) / (math.pi * MODULE * math.cos(ALPHA))
J_A, J_B = 0.0015, 0.006
MEAN = 1.3e9  # c_γα·b [N/m]


def _pair(attributes: str):
    text = two_gear_urdf().replace(
        '<mesh name="m" gear1="g1" gear2="g2"/>',
        f'<mesh name="m" gear1="g1" gear2="g2" type="compliant" {attributes}/>',
    )
    return loads(text, "pair.urdf")


@pytest.mark.parametrize("variation", ["constant", "path"])
def test_the_mean_stiffness_given_is_the_mean_the_mesh_has(variation):
    gb = _pair(f'mean_stiffness="{MEAN!r}" stiffness_variation="{variation}" damping="0"')
    mesh = gb.mesh("m")
    # ISO's relation backwards gives the single-pair stiffness.
    assert_allclose(single_pair(mesh), MEAN / (0.75 * CONTACT_RATIO + 0.25), rtol=1e-9)
    assert_allclose(mean_mesh_stiffness(mesh), MEAN, rtol=1e-12)
    setup = mesh_setup(gb, mesh_choices(gb, None), driver_index=[], dt=None)
    assert_allclose(setup.compliant[0].stiffness, MEAN, rtol=1e-12)
    table = pair_table(mesh)
    if variation == "constant":
        assert table is None
        return
    # The path's pair curve, summed over the pairs in contact and averaged over a base pitch,
    # is ∫ k(s) ds / p_bt over the path (each pair runs the whole path once per base pitch):
    # exact for the piecewise-linear table by the trapezoidal rule.
    s, k = table
    base_pitch = math.pi * MODULE * math.cos(ALPHA)
    integral = float(np.sum(0.5 * (k[1:] + k[:-1]) * np.diff(s)))
    assert_allclose(integral / base_pitch, MEAN, rtol=1e-9)


def test_the_mean_from_the_single_pair_stiffness_is_iso_s_relation():
    single = 1e9  # c′·b [N/m]
    by_single = _pair(f'stiffness="{single!r}"').mesh("m")
    expected_mean = single * (0.75 * CONTACT_RATIO + 0.25)
    by_mean = _pair(f'mean_stiffness="{expected_mean!r}"').mesh("m")
    assert_allclose(single_pair(by_mean), single, rtol=1e-9)
    s1, k1 = pair_table(by_single)
    s2, k2 = pair_table(by_mean)
    assert_allclose(s2, s1, rtol=0, atol=0)
    assert_allclose(k2, k1, rtol=1e-9)


def test_the_mesh_mode_takes_the_mean_stiffness_given():
    gb = _pair(f'mean_stiffness="{MEAN!r}" damping="0"')
    found = [m.frequency for m in linearise(gb).modes() if m.frequency > 0]
    omega = math.sqrt(MEAN * (RB1**2 / J_A + RB2**2 / J_B))
    assert_allclose(found, [omega / (2 * math.pi)], rtol=1e-9)


@pytest.mark.parametrize(
    ("attributes", "message"),
    [
        ('mean_stiffness="1e9" stiffness="1e9"', "mean_stiffness .* and stiffness both"),
        ('mean_stiffness="1e9" pair_stiffness="0:1e9 1:1e9"', "and pair_stiffness both"),
        ('mean_stiffness="-1e9"', "mean stiffness is -1e\\+09 N/m"),
    ],
)
def test_a_mean_stiffness_with_another_stiffness_or_not_positive_is_refused(attributes, message):
    with pytest.raises(MalformedModel, match=message):
        _pair(attributes)


def test_a_mean_stiffness_on_a_rigid_mesh_is_refused():
    text = two_gear_urdf().replace(
        '<mesh name="m" gear1="g1" gear2="g2"/>',
        '<mesh name="m" gear1="g1" gear2="g2" mean_stiffness="1e9"/>',
    )
    with pytest.raises(MalformedModel, match="mean_stiffness only apply to a compliant mesh"):
        loads(text, "pair.urdf")
