"""Modes at speed (``modes/gyroscopic_modes.py``): a spinning rotor on a compliant bearing.

A rigid rotor (mass m, polar inertia J_p, transverse J_t about its centre, the bearing centre) on
an isotropic bearing of radial stiffness k and tilt stiffness k_t, spinning at Ω about z. Small
tilts θ_x, θ_y about the bearing's radial axes obey (Euler's equations, the spin's angular
momentum J_p Ω turned by the tilt rates)

    J_t θ̈_x + J_p Ω θ̇_y + k_t θ_x = 0,    J_t θ̈_y − J_p Ω θ̇_x + k_t θ_y = 0.

With θ_x + i θ_y ∝ e^{iωt} (an orbit of the axis turning with the spin for ω > 0): J_t ω² −
J_p Ω ω − k_t = 0, so the forward and backward whirl frequencies are

    ω_f,b = (± J_p Ω + √((J_p Ω)² + 4 J_t k_t)) / (2 J_t)        (Jeffcott / Stodola-Green),

both √(k_t/J_t) at Ω = 0. The centre translates as m ẍ + k x = 0 whatever the spin (the centre of
mass on the axis feels no Coriolis force in fixed axes): √(k/m) at every speed. A radial damper c
makes the translation m ẍ + c ẋ + k x = 0: λ = −c/2m ± i √(k/m − (c/2m)²), so |λ| = √(k/m) and
−Re λ/|λ| = c / (2 √(k m)). The same rotor, spun up and struck, rings at both whirl frequencies
(the peaks of its tilt's spectrum, ``test_normal_modes._spectral_peaks``).
"""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import numpy as np
import pytest

import pinwind
from pinwind.dynamics import Integrator
from pinwind.errors import PinwindWarning, SpeedOutOfRange
from pinwind.model.gearbox import Gearbox, loads
from pinwind.modes.linearisation import linearise
from pinwind.modes.mode_animation import mode_motion
from tests.dynamics.test_normal_modes import _spectral_peaks

MASS, RADIAL, TILT = 10.0, 1e6, 1e4
#: (J_p, J_t) [kg·m²]: a long rotor (J_p < J_t, whose forward whirl meets the 1× line) and a
#: thin disc (J_p = 2 J_t, whose forward whirl stays above it).
ROTORS = [(0.2, 0.5), (0.4, 0.2)]


def rotor_urdf(polar: float, transverse: float, bearing: str = "") -> str:
    """A rotor on bearing "rotor" (axis z) with radial and tilt springs, centre on the bearing."""
    return f"""<robot name="rotor">
  <link name="ground"/>
  <link name="rotor"><inertial><mass value="{MASS!r}"/>
    <inertia ixx="{transverse!r}" iyy="{transverse!r}" izz="{polar!r}" ixy="0" ixz="0" iyz="0"/>
  </inertial></link>
  <joint name="rotor" type="continuous"><parent link="ground"/><child link="rotor"/>
    <origin xyz="0.1 -0.2 0.3"/><axis xyz="0 0 1"/></joint>
  <gearbox>
    <bearing joint="rotor" radial_stiffness="{RADIAL!r}" tilt_stiffness="{TILT!r}" {bearing}/>
  </gearbox>
</robot>"""


def rotor(polar: float, transverse: float, bearing: str = "") -> Gearbox:
    return loads(rotor_urdf(polar, transverse, bearing), "rotor.urdf")


def whirl_frequencies(polar: float, transverse: float, spin: float) -> tuple[float, float]:
    """(ω_f, ω_b) [rad/s], module docstring."""
    root = math.sqrt((polar * spin) ** 2 + 4 * transverse * TILT)
    return (polar * spin + root) / (2 * transverse), (-polar * spin + root) / (2 * transverse)


def _tilt_modes(modes):
    return [m for m in modes if m.kinetic_share["rotor_tilt_x"] + m.kinetic_share["rotor_tilt_y"]
            > 0.99]  # fmt: skip


@pytest.mark.parametrize(("polar", "transverse"), ROTORS)
@pytest.mark.parametrize("spin", [30.0, 300.0, 3000.0])
def test_a_spinning_rotor_s_tilt_modes_split_into_forward_and_backward_whirl_by_the_closed_form(
    polar, transverse, spin
):
    modes = linearise(rotor(polar, transverse), speeds={"rotor": spin}).modes()
    tilt = {m.whirl: m.frequency * 2 * math.pi for m in _tilt_modes(modes)}
    forward, backward = whirl_frequencies(polar, transverse, spin)
    assert set(tilt) == {"forward", "backward"}
    np.testing.assert_allclose(tilt["forward"], forward, rtol=1e-6)
    np.testing.assert_allclose(tilt["backward"], backward, rtol=1e-6)
    for m in _tilt_modes(modes):
        np.testing.assert_allclose(m.damping_ratio, 0.0, atol=1e-9)  # no damper: no decay


@pytest.mark.parametrize(("polar", "transverse"), ROTORS)
def test_at_rest_both_tilt_modes_ring_at_root_kt_over_jt(polar, transverse):
    modes = linearise(rotor(polar, transverse)).modes()
    expected = math.sqrt(TILT / transverse)
    np.testing.assert_allclose(whirl_frequencies(polar, transverse, 0.0), expected, rtol=1e-12)
    tilt = [m.frequency * 2 * math.pi for m in _tilt_modes(modes)]
    np.testing.assert_allclose(tilt, [expected, expected], rtol=1e-9)
    assert {m.whirl for m in modes} == {""}  # no spin, no whirl


@pytest.mark.parametrize("spin", [0.0, 300.0, 3000.0])
def test_a_spinning_rotor_s_centre_translates_at_root_k_over_m_at_every_speed(spin):
    # G must not leak into the translation of the centre of mass (module docstring).
    modes = linearise(rotor(*ROTORS[0]), speeds={"rotor": spin}).modes()
    radial = [
        m.frequency
        for m in modes
        if m.kinetic_share["rotor_radial_x"] + m.kinetic_share["rotor_radial_y"] > 0.99
    ]
    np.testing.assert_allclose(radial, [math.sqrt(RADIAL / MASS) / (2 * math.pi)] * 2, rtol=1e-9)


def test_a_radial_damper_at_speed_gives_root_k_over_m_and_its_damping_ratio():
    damping = 2e3
    gb = rotor(*ROTORS[0], bearing=f'radial_damping="{damping!r}"')
    lin = linearise(gb, speeds={"rotor": 300.0})
    assert lin.speed_terms_act()  # the quadratic solve
    radial = [
        m
        for m in lin.modes()
        if m.kinetic_share["rotor_radial_x"] + m.kinetic_share["rotor_radial_y"] > 0.99
    ]
    assert len(radial) == 2
    for m in radial:
        np.testing.assert_allclose(m.frequency, math.sqrt(RADIAL / MASS) / (2 * math.pi), rtol=1e-9)
        np.testing.assert_allclose(
            m.damping_ratio, damping / (2 * math.sqrt(RADIAL * MASS)), rtol=1e-9
        )


def test_spun_the_other_way_the_higher_tilt_mode_still_whirls_forward():
    # The same rotor spun about −z (the joint axis flipped): the higher mode still turns with the
    # spin, so it stays the forward one.
    polar, transverse = ROTORS[0]
    text = rotor_urdf(polar, transverse).replace('<axis xyz="0 0 1"/>', '<axis xyz="0 0 -1"/>')
    modes = linearise(loads(text, "rotor.urdf"), speeds={"rotor": 300.0}).modes()
    tilt = {m.whirl: m.frequency * 2 * math.pi for m in _tilt_modes(modes)}
    forward, backward = whirl_frequencies(polar, transverse, 300.0)
    np.testing.assert_allclose([tilt["forward"], tilt["backward"]], [forward, backward], rtol=1e-6)


def test_the_strain_energy_of_a_whirl_mode_is_all_in_the_tilt_springs():
    modes = linearise(rotor(*ROTORS[0]), speeds={"rotor": 300.0}).modes()
    for m in _tilt_modes(modes):
        shares = m.strain_share
        np.testing.assert_allclose(shares["rotor_tilt_x"] + shares["rotor_tilt_y"], 1.0, rtol=1e-9)
        np.testing.assert_allclose(shares["rotor_tilt_x"], 0.5, rtol=1e-9)  # a circular orbit


def test_a_stage_whose_sun_translates_in_the_ground_is_refused_at_speed_naming_the_carrier():
    # The sun's slides are fixed to the ground while the carrier carries the sun-planet lines of
    # action round: the sun's coefficients are periodic in the carrier's angle.
    text = Path("models/saleh2017_planetary.urdf").read_text()
    text = text.replace("</gearbox>", '<bearing joint="sun" radial_stiffness="1e9"/></gearbox>')
    gb = loads(text, "stage.urdf")
    assert linearise(gb, meshes={"all": "compliant"}).modes()  # at rest: no time
    with pytest.raises(SpeedOutOfRange, match="act on carrier.*linearise at speed 0"):
        linearise(gb, meshes={"all": "compliant"}, speeds={"carrier": 10.0})


def test_the_whirl_frequencies_are_the_peaks_of_the_spinning_rotor_s_free_vibration():
    # The rotor spun up to 300 rad/s, free, its tilt struck by a 1 ms moment: its axis rings at
    # both whirl frequencies. 2e-4 s steps, ≥ 140 per period: the trapezoidal rule's frequency
    # error (ωh)²/12 < 2e-4.
    polar, transverse = ROTORS[0]
    spin, dt = 300.0, 2e-4
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PinwindWarning)
        res = pinwind.simulate(
            rotor(polar, transverse),
            duration=10.0,
            dt=dt,
            gravity=np.zeros(3),
            initial_deflection="none",
            initial_speeds={"rotor": spin},
            torques={"rotor_tilt_x": lambda t: 100.0 if t < 1e-3 else 0.0},
            integrator=Integrator(rho_infinity=1.0),
        )
    peaks = _spectral_peaks(np.asarray(res.joint("rotor_tilt_x").angle), dt, 2)
    forward, backward = whirl_frequencies(polar, transverse, spin)
    np.testing.assert_allclose(
        peaks, [backward / (2 * math.pi), forward / (2 * math.pi)], rtol=5e-3
    )
    modes = linearise(rotor(polar, transverse), speeds={"rotor": spin}).modes()
    tilt = sorted(m.frequency for m in _tilt_modes(modes))
    np.testing.assert_allclose(peaks, tilt, rtol=5e-3)


def test_an_animated_whirl_mode_turns_the_rotor_s_axis_round_a_circle():
    # A circular whirl: the tilt angles keep one magnitude through the animation.
    modes = linearise(rotor(*ROTORS[0]), speeds={"rotor": 300.0}).modes()
    (forward,) = [m for m in modes if m.whirl == "forward"]
    gb = rotor(*ROTORS[0])
    motion = mode_motion(gb, forward, periods=1)
    tilt = motion.angle[:, [motion.joint_names.index(f"rotor_tilt_{a}") for a in "xy"]]
    radius = np.hypot(tilt[:, 0], tilt[:, 1])
    np.testing.assert_allclose(radius, radius.max(), rtol=1e-9)
    assert radius.max() > 0.0
