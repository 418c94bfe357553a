"""Every planet bearing of the Saleh stage under rated load, from the free body of the planet.

Saleh 2017: ring fixed, carrier 1 MN·m, sun −1e6/6 N·m (balanced).
Planet i sits at angle φ_i = (i − 1)·120° on the carrier at a = r_s + r_p = 0.54 m; e_r and e_t are
the radial and tangential unit vectors there. By hand, independently of pinwind's conventions:

- Sun torque balance: the three planets push the sun forward with F_t each at r_s, so
  3 r_s F_t = −T_sun and F_t = (1e6/6)/(3 · 0.18 m) = 308.6 kN. By reaction the sun pushes each
  planet backwards: −F_t e_t.
- Planet spin balance about its own centre (it turns at constant speed): the ring's tangential
  force on the planet equals the sun's, −F_t e_t, on the other side of the planet.
- Involute line of action: the contact force is along the common normal of the flanks, at the
  working pressure angle α_w (24.5°, no profile shift) to the common tangent e_t, tilted so that it
  pushes the two gears apart. Apart from the sun (centre inside) is +e_r; apart from the ring
  (teeth outside, towards the centre of the ring) is −e_r. So, with F_n = F_t / cos α_w:
      sun on planet  = F_n (−cos α_w e_t + sin α_w e_r)
      ring on planet = F_n (−cos α_w e_t − sin α_w e_r)
- Newton for the planet: bearing force (carrier pin on planet) + sun + ring + m g = m a_centre, with
  a_centre = −ω_c² a e_r when the carrier turns at constant ω_c.

Flipping the radial direction of either mesh moves each planet bearing force by 2 F_n sin α_w =
281 kN; the tests below catch that with either gear of the ring mesh written first.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

import pinwind
from pinwind.model.gearbox import loads
from tests.conftest import MODELS

T_CARRIER = 1e6  # N·m, rated rotor torque, Saleh 2017 §4.1
T_SUN = -T_CARRIER / 6
MODULE, ALPHA = 0.015, math.radians(24.5)
R_SUN, R_PLANET = 24 * MODULE / 2, 48 * MODULE / 2
A = R_SUN + R_PLANET
M_PLANET = 1113.1  # kg, Table 3
G = np.array([0.0, -9.81, 0.0])  # the model's gravity
F_T = -T_SUN / (3 * R_SUN)
F_N = F_T / math.cos(ALPHA)
OMEGA_RATED = 14.2 * 2 * math.pi / 60  # rad/s


def swapped_ring_meshes(text: str) -> str:
    """The shipped model with the ring written as gear1 (A) of every ring mesh."""
    for i in (1, 2, 3):
        old = f'gear1="planet{i}" gear2="ring"'
        assert old in text
        text = text.replace(old, f'gear1="ring" gear2="planet{i}"')
    return text


@pytest.fixture(scope="module", params=["ring as gear2 (shipped)", "ring as gear1"])
def model(request):
    text = (MODELS / "saleh2017_planetary.urdf").read_text()
    if request.param == "ring as gear1":
        return loads(swapped_ring_meshes(text), path="saleh_ring_first.urdf")
    return loads(text, path="saleh2017_planetary.urdf")


def unit_vectors(phi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(e_r, e_t) at angles phi, shape (n, 3)."""
    zero = np.zeros_like(phi)
    e_r = np.stack([np.cos(phi), np.sin(phi), zero], axis=-1)
    e_t = np.stack([-np.sin(phi), np.cos(phi), zero], axis=-1)
    return e_r, e_t


def tooth_forces_on_planet(phi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(sun on planet, ring on planet) [N] by hand, see the module docstring."""
    e_r, e_t = unit_vectors(phi)
    sun = F_N * (-math.cos(ALPHA) * e_t + math.sin(ALPHA) * e_r)
    ring = F_N * (-math.cos(ALPHA) * e_t - math.sin(ALPHA) * e_r)
    return sun, ring


def run(gb, **kwargs) -> pinwind.Result:
    return pinwind.simulate(
        gb, duration=0.2, dt=1e-3, torques={"carrier": T_CARRIER, "sun": T_SUN}, **kwargs
    )


def test_tooth_forces_on_each_planet_lie_on_the_line_of_action_and_separate_the_gears(model):
    res = run(model)
    for i in (1, 2, 3):
        phi = np.full(len(res), math.radians(120 * (i - 1)))
        sun, ring = tooth_forces_on_planet(phi)
        assert_allclose(res.mesh(f"sun_planet{i}").force_on_b, sun, rtol=0, atol=1e-6 * F_N)
        ring_mesh = res.mesh(f"planet{i}_ring").force_on_b
        if model.mesh(f"planet{i}_ring").gear_b.name == "ring":  # the planet's push on the ring
            assert_allclose(ring_mesh, -ring, rtol=0, atol=1e-6 * F_N)
        else:  # the ring written as gear1: B is the planet
            assert_allclose(ring_mesh, ring, rtol=0, atol=1e-6 * F_N)


def test_every_planet_bearing_carries_its_tooth_forces_and_its_weight_at_rated_load(model):
    res = run(model)
    for i in (1, 2, 3):
        phi = np.full(len(res), math.radians(120 * (i - 1)))
        sun, ring = tooth_forces_on_planet(phi)
        expected = -(sun + ring) - M_PLANET * G
        bearing = res.bearing(f"planet{i}")
        assert_allclose(bearing.force, expected, rtol=0, atol=1e-6 * F_N)
        # The pin passes no torque to a free-turning planet, and the forces act in one plane.
        assert_allclose(bearing.moment, 0.0, atol=1e-6 * F_N * A)
    # Magnitude check: 2 F_t along e_t plus the weight, e.g. planet 1 (φ = 0, e_t = +y).
    assert_allclose(res.bearing("planet1").force[-1, 1], 2 * F_T + M_PLANET * 9.81, rtol=1e-12)


def test_every_planet_bearing_adds_the_centripetal_force_at_rated_speed(model):
    # Balanced torques at 14.2 rpm: the carrier turns at constant speed, each planet centre
    # accelerates towards the axis with ω² a, which its bearing must supply.
    res = run(model, initial_speeds={"carrier": OMEGA_RATED})
    assert_allclose(res.joint("carrier").speed, OMEGA_RATED, rtol=1e-12)
    theta = res.joint("carrier").angle
    for i in (1, 2, 3):
        phi = math.radians(120 * (i - 1)) + theta
        sun, ring = tooth_forces_on_planet(phi)
        e_r, _ = unit_vectors(phi)
        centripetal = -M_PLANET * OMEGA_RATED**2 * A * e_r
        expected = M_PLANET * (-G) - sun - ring + centripetal
        assert_allclose(res.bearing(f"planet{i}").force, expected, rtol=0, atol=1e-6 * F_N)
    # The centripetal term is 1.33 kN, far above the tolerance: the test would see it missing.
    assert M_PLANET * OMEGA_RATED**2 * A > 1e3 * 1e-6 * F_N
