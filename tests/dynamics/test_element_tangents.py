"""Every element's tangent is the derivative of its force, and its force the gradient of its energy.

The step takes each stiff element implicitly with its tangents K = −∂f/∂q, C = −∂f/∂v
(``CompiledStepper.element_forces``); ``pinwind.testing.element_tangents`` compares them with
central differences of f at seeded states, ``conservative_forces`` compares f at rest with −∇U
(docs/testing.md). Each model here holds one element kind, so that a failure names it.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from pinwind.errors import PinwindWarning
from pinwind.model.gearbox import loads
from pinwind.testing import conservative_forces, element_tangents
from pinwind.testing.tangents import element_stepper, seeded_states
from tests.dynamics.test_compliant_bearing import disc_urdf
from tests.dynamics.test_flank_contact import _floating_stage, pair_urdf
from tests.dynamics.test_support import supported_pair, tower
from tests.dynamics.test_torsional_spring import _shafts_urdf

#: The tolerance issue 36 asks of every element's tangent.
RTOL = 1e-6
#: The disc's radial clearance [m] and the states' spread about the centre [m]: most states
#: press the disc against the bearing, some leave it inside the clearance.
CLEARANCE, SPREAD = 5e-6, 10e-6


def _quiet(text: str):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PinwindWarning)
        return loads(text)


def test_a_compliant_mesh_on_fixed_axes_has_the_tangents_of_its_force():
    """Constant stiffness, damped: K = k JᵀJ and C = c JᵀJ on the flank in contact."""
    gb = _quiet(pair_urdf(bearing="", mesh='stiffness_variation="constant" damping="2000"'))
    element_tangents(gb, states=8, seed=1, rtol=RTOL)
    conservative_forces(gb, states=8, seed=1, rtol=RTOL)


def test_a_compliant_mesh_with_backlash_has_the_tangents_of_its_force_on_either_flank():
    """The seeded turns (±5 µm at the pitch circle) put the teeth on either flank or in the
    0.004 mm backlash (no force, no tangent)."""
    gb = _quiet(pair_urdf(bearing="", mesh='stiffness_variation="constant" backlash_mm="0.004"'))
    element_tangents(gb, states=12, seed=2, rtol=RTOL)
    conservative_forces(gb, states=12, seed=2, rtol=RTOL)


def test_a_mesh_whose_centres_move_pushes_along_the_gradient_of_its_flanks_energy():
    """A pinion in a compliant bearing: the step's tangent is Gauss-Newton (k JᵀJ, without the
    curvature of the line of action as the centre distance changes), so the force is compared
    with −∇U, U = Σ_flanks ½ k δ₊², instead."""
    gb = _quiet(pair_urdf(mesh='stiffness_variation="constant" damping="0"'))
    figure = conservative_forces(gb, states=12, seed=3, rtol=RTOL)
    assert figure.measured <= RTOL


def test_a_floating_planetary_stage_pushes_along_the_gradient_of_its_meshes_energy():
    """Lin & Parker's four-planet stage, every member in a radial bearing: both flanks of
    every sun- and ring-planet mesh in play."""
    gb = _floating_stage()
    conservative_forces(gb, states=4, seed=4, rtol=RTOL, meshes={"all": "compliant"})


def test_a_torsional_spring_with_a_preload_and_damping_has_the_tangents_of_its_torque():
    gb = _quiet(_shafts_urdf(stiffness=5e4, spring_damping=30.0, preload=0.01))
    element_tangents(gb, states=6, seed=5, rtol=RTOL)
    conservative_forces(gb, states=6, seed=5, rtol=RTOL)


def test_a_linear_bearing_in_radial_axial_and_tilt_has_the_tangents_of_its_springs():
    gb = _quiet(
        disc_urdf(
            'radial_stiffness="1e8" radial_damping="300" axial_stiffness="5e7" '
            'axial_damping="100" tilt_stiffness="2e6" tilt_damping="10"'
        )
    )
    element_tangents(gb, states=6, seed=6, rtol=RTOL)
    conservative_forces(gb, states=6, seed=6, rtol=RTOL)


@pytest.mark.parametrize("contact", ["line", "point"])
def test_a_roller_sum_bearing_with_clearance_has_the_tangent_of_its_rollers(contact):
    """Harris's sum over 12 rollers with 2 µm clearance: K = Σ n K_n δⁿ⁻¹ e eᵀ of the rollers
    in contact (the law is smooth but at first contact, where the states are left out)."""
    gb = _quiet(
        disc_urdf(
            f'law="roller_sum" rollers="12" contact_stiffness="1e9" contact="{contact}" '
            'radial_clearance_mm="0.002" radial_damping="200"'
        )
    )
    figure = element_tangents(gb, states=10, seed=7, rtol=RTOL)
    assert "10 states" in figure.detail
    conservative_forces(gb, states=10, seed=7, rtol=RTOL)


def test_support_mounts_and_tower_slides_have_the_tangents_of_their_springs():
    support = (
        '<support housing="housing"><mount stiffness_x="5e8" stiffness_y="4e8" '
        'stiffness_z="3e8" stiffness_roll="2e7" damping_x="1e3" damping_roll="50"/>'
        + tower("fore_aft", 0.7, 2e4, 0.01)
        + tower("vertical", 8.0, 1e4, 0.02)
        + "</support>"
    )
    gb = _quiet(supported_pair(support))
    element_tangents(gb, states=6, seed=8, rtol=RTOL)
    conservative_forces(gb, states=6, seed=8, rtol=RTOL)


def _outside_the_clearance(gb, count: int) -> list[tuple[np.ndarray, np.ndarray]]:
    """Seeded states of the disc pressed beyond its clearance (|r| > 1.5 c)."""
    states = seeded_states(gb, 4 * count, seed=9, spread_m=SPREAD)
    x, y = gb.v_index("disc_radial_x"), gb.v_index("disc_radial_y")
    out = [(q, v) for q, v in states if np.hypot(q[x], q[y]) > 1.5 * CLEARANCE]
    assert len(out) >= count
    return out[:count]


def test_a_bearing_pressed_beyond_its_clearance_has_the_tangent_of_its_law():
    """F = −k (|r| − c) r̂ beyond the clearance: its tangent k [(1 − c/|r|) I + (c/|r|) r̂ r̂ᵀ]
    is stiffer along r̂ than across it, which central differences of F see."""
    gb = _quiet(
        disc_urdf(
            f'radial_stiffness="1e8" radial_damping="300" radial_clearance_mm="{CLEARANCE * 1e3!r}"'
        )
    )
    states = _outside_the_clearance(gb, 6)
    stepper = element_stepper(gb)
    x, y = gb.v_index("disc_radial_x"), gb.v_index("disc_radial_y")
    for q, v in states:  # in contact: the law pushes and has a tangent
        at = stepper.element_forces(q, v)
        assert np.hypot(at.force[x], at.force[y]) > 0.0
        assert at.stiffness[x, x] + at.stiffness[y, y] > 0.0
    element_tangents(gb, states=states, rtol=RTOL, spread_m=SPREAD)
    conservative_forces(gb, states=states, rtol=RTOL, spread_m=SPREAD)


def test_a_bearing_with_clearance_pushes_along_the_gradient_of_its_energy():
    gb = _quiet(disc_urdf(f'radial_stiffness="1e8" radial_clearance_mm="{CLEARANCE * 1e3!r}"'))
    conservative_forces(gb, states=8, seed=10, rtol=RTOL, spread_m=SPREAD)


def test_bearing_rows_off_their_stiffness_centre_have_the_tangents_of_their_springs():
    """Two damped rows with K_y ≠ K_z and tilt springs, Σ k a ≠ 0: the radial and tilt
    slides couple (cpp/bearing_rows.hpp)."""
    from tests.dynamics.test_row_springs import _row, shaft_on_rows

    rows = [
        _row("A", -0.3, (2e7, 1e8, 3e8, 1e5, 2e5), (10.0, 300.0, 200.0, 1.0, 2.0)),
        _row("B", 0.2, (1e7, 2e8, 5e7, 3e5, 0.0), (20.0, 100.0, 400.0, 3.0, 0.5)),
    ]
    gb = _quiet(shaft_on_rows(rows))
    element_tangents(gb, states=6, seed=11, rtol=RTOL)
    conservative_forces(gb, states=6, seed=11, rtol=RTOL)


def test_a_bearings_friction_moment_has_the_tangent_of_its_moment_on_every_branch():
    """Palmgren's M0 ∝ (ν n)^(2/3) above its floor, the floor, and the regularised sign through
    ω = 0 (|ω| < ω_s): the speeds chosen so each branch holds a state and none sits on a kink."""
    from tests.dynamics.test_bearing_friction_step import shaft

    gb = _quiet(shaft())
    speeds = (-30.0, -2.0, -0.004, 0.003, 0.5, 12.0, 100.0)  # [rad/s]
    states = [(np.zeros(1), np.array([w])) for w in speeds]
    figure = element_tangents(gb, states=states, rtol=RTOL)
    assert "7 states" in figure.detail
