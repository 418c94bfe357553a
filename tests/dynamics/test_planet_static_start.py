"""The static start of planets on compliant bearings under rigid meshes: an equilibrium.

A rigid mesh row carries its load on one flank; the other flank's line of action is the mirror
image of the first about the centre line (n = s cos α_w t + ε sin α_w r̂). On fixed axes the
other flank's row is the same row reversed, so the flank does not matter to a static solve; on
a planet that can move on its bearing it does. By hand, for a planet of a stage with the carrier
held and a torque T on the sun (Saleh et al. 2017's stage: 24/48/120
teeth, module 15 mm, α_w = 24.5° on both meshes, a = 0.54 m, planet 1113.1 kg (Table 3)):

- planet spin: the sun's and the ring's lines of action pass the planet centre at the same arm
  (the pitch points split the centre line in the ratio of the base radii, r_b,p on both sides),
  so both tooth forces are equal, F_n;
- both push the planet backwards along −e_t with F_n cos α_w, and their radial parts
  ±F_n sin α_w cancel: the bearing carries B = 2 F_n cos α_w along e_t of the planet's centre
  line, and the planet moves by −B e_t / k on its slides, at right angles to its final centre
  line; so the centre distance becomes d = √(a² − (B/k)²), turned by δ = −asin(B/(k a));
- the sun: three lines of action at the arm (d/3) cos α_w about its axis carry T, so
  F_n = T / (d cos α_w) and B = 2 T / d;
- with gravity g, each planet's bearing also carries its weight m g, and the rigid rows keep the
  planets' tangential positions equal (e_t·u_i the same for all): 2 F_n,i cos α_w − e_t,i·m g is
  the same for every planet, so F_n,i = F̄_n + e_t,i·m g / (2 cos α_w) (to first order in the
  deflection: the rows turn with the centre lines by u/a ≈ 1.1e-3, which moves the weight's share
  m g/(2 cos α_w) ≈ 6 kN by ≈ 7 N, 2e-5 of F_n).

Before the static start switched the rigid rows' flanks as the step does, it left the sun meshes
on their pulling flank: the radial parts added, the planet sat 0.28 mm off radially and
accelerated at 229 m/s² at t = 0.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

import pinwind
from pinwind.model.gearbox import load, loads
from tests.conftest import MODELS

T_SUN = 1e6 / 6  # N·m on the sun (Saleh 2017 §4.1: 1 MN·m over the ratio 6)
MODULE, ALPHA = 0.015, math.radians(24.5)
A = (24 + 48) * MODULE / 2  # centre distance [m]
M_PLANET = 1113.1  # kg (Table 3)
K_BEARING = 1e9  # planet bearing radial stiffness [N/m]
G = 9.81  # the model's gravity, along −y [m/s²]


def loaded_centre_distance() -> float:
    """d = √(a² − (B/k)²) with B = 2 T / d, by fixed-point iteration [m].

    B/k ≈ 0.6 mm on a = 0.54 m: each pass shrinks the error by (B/(k a))² ≈ 1e-6.
    """
    d = A
    for _ in range(8):
        d = math.sqrt(A**2 - (2 * T_SUN / (d * K_BEARING)) ** 2)
    return d


D = loaded_centre_distance()
B = 2 * T_SUN / D  # the planet bearing's load [N]
F_N = T_SUN / (D * math.cos(ALPHA))
#: Every joint acceleration at t = 0 [m/s² or rad/s²] below 1e-9 of B / m_planet (555 m/s², the
#: acceleration the bearing's load would give the planet unbalanced); the sun's T / J_sun is
#: larger (3.4e4 rad/s²), so the tolerance is the tighter of the two.
ACCELERATION_TOL = 1e-9 * B / M_PLANET


def saleh_on_planet_bearings() -> pinwind.Gearbox:
    text = (MODELS / "saleh2017_planetary.urdf").read_text()
    extra = "".join(
        f'  <bearing joint="planet{i}" radial_stiffness="{K_BEARING:g}" radial_damping="2e5"/>\n'
        for i in (1, 2, 3)
    )
    return loads(text.replace("</gearbox>", extra + "</gearbox>"), "saleh_planet_bearings.urdf")


def start(gravity: np.ndarray | None = None) -> pinwind.Result:
    return pinwind.simulate(
        saleh_on_planet_bearings(),
        duration=1e-3,  # ten steps: StepTooCoarse asks for at least ten
        dt=1e-4,
        speeds={"carrier": 0.0},
        torques={"sun": -T_SUN},
        gravity=gravity,
    )


def unit_vectors(phi: float) -> tuple[np.ndarray, np.ndarray]:
    """(e_r, e_t) at angle phi about the stage axis."""
    return np.array([math.cos(phi), math.sin(phi), 0.0]), np.array(
        [-math.sin(phi), math.cos(phi), 0.0]
    )


def accelerations_at_start(res: pinwind.Result, gearbox: pinwind.Gearbox) -> np.ndarray:
    return np.array([res.joint(n).acceleration[0] for n in gearbox.joint_names])


@pytest.fixture(scope="module")
def weightless() -> pinwind.Result:
    return start(np.zeros(3))


@pytest.fixture(scope="module")
def with_weight() -> pinwind.Result:
    return start()


@pytest.mark.parametrize("case", ["weightless", "with_weight"])
def test_planets_on_compliant_bearings_under_rigid_meshes_start_at_rest(case, request):
    res = request.getfixturevalue(case)
    assert res.metadata["initial_deflection"]["converged"]
    acceleration = accelerations_at_start(res, saleh_on_planet_bearings())
    assert_allclose(acceleration, 0.0, rtol=0, atol=ACCELERATION_TOL)


def test_a_planet_bearing_carries_its_sun_and_ring_tooth_forces_and_is_deflected_by_them(
    weightless,
):
    delta = -math.asin(B / (K_BEARING * A))
    for i in (1, 2, 3):
        e_r, e_t = unit_vectors(math.radians(120 * (i - 1)) + delta)
        assert_allclose(weightless.mesh(f"sun_planet{i}").normal[0], F_N, rtol=1e-9)
        assert_allclose(weightless.mesh(f"planet{i}_ring").normal[0], F_N, rtol=1e-9)
        bearing = weightless.bearing(f"planet{i}")
        assert_allclose(bearing.force[0], B * e_t, rtol=0, atol=1e-9 * B)
        assert_allclose(
            bearing.displacement[0], -B * e_t / K_BEARING, rtol=0, atol=1e-9 * B / K_BEARING
        )
        position = weightless.body(f"planet{i}").position[0]
        assert_allclose(position, D * e_r, rtol=0, atol=1e-9 * B / K_BEARING)


def test_with_their_weights_the_planets_share_the_sun_torque_by_their_tangential_deflection(
    with_weight,
):
    weight = np.array([0.0, -M_PLANET * G, 0.0])
    moment = 0.0
    for i in (1, 2, 3):
        sun = with_weight.mesh(f"sun_planet{i}").normal[0]
        assert_allclose(with_weight.mesh(f"planet{i}_ring").normal[0], sun, rtol=1e-9)
        centre = with_weight.body(f"planet{i}").position[0]
        e_r = centre / np.linalg.norm(centre)
        # The tooth forces' radial parts cancel at the planet's own centre line: the bearing's
        # radial load is the weight's alone.
        teeth = with_weight.bearing(f"planet{i}").force[0] + weight
        assert_allclose(teeth @ e_r, 0.0, rtol=0, atol=1e-9 * B)
        assert_allclose(np.linalg.norm(teeth), 2 * sun * math.cos(ALPHA), rtol=1e-9)
        moment += np.linalg.norm(teeth) * np.linalg.norm(centre) / 3  # at the sun's pitch radius
        expected = F_N + (unit_vectors(math.radians(120 * (i - 1)))[1] @ weight) / (
            2 * math.cos(ALPHA)
        )
        assert_allclose(sun, expected, rtol=1e-4)
    # The sun's moment balance: the planets' tangential loads, 2 F_n,i cos α_w each, at the
    # sun's working pitch radius d_i / 3, carry twice the sun torque.
    assert_allclose(moment, 2 * T_SUN, rtol=1e-9)


# The NREL 5 MW gearbox (Nejad et al. 2016; models/nrel5mw_gearbox.urdf) at rated: 5 MW at
# 12.1 rpm (Jonkman et al. 2009), the generator held at the teeth's ratio.
RPM = 2 * math.pi / 60
ROTOR_TORQUE = 3945990.3245924464  # N·m, 5e6 W / (12.1 rpm)
GENERATOR_SPEED = -1165.8854166666667 * RPM
ROTOR_SPEED = 12.1 * RPM
#: Stage 1 (Nejad et al. 2016 Table V): sun 19, planets 17, ring 56 teeth, module 45 mm, 20°,
#: spur; ring fixed, carrier on the rotor, so the sun carries T z_s / (z_s + z_r).
Z_SUN, Z_RING, MODULE_1, ALPHA_1 = 19, 56, 0.045, math.radians(20.0)
R_B_SUN_1 = Z_SUN * MODULE_1 * math.cos(ALPHA_1) / 2
#: Stage 2's sun: 18 teeth, module 21 mm, 20°, spur (Table V).
R_B_SUN_2 = 18 * 0.021 * math.cos(math.radians(20.0)) / 2


@pytest.fixture(scope="module")
def rated_5mw() -> tuple[pinwind.Gearbox, pinwind.Result]:
    gearbox = load(MODELS / "nrel5mw_gearbox.urdf")
    res = pinwind.simulate(
        gearbox,
        duration=1e-3,  # ten steps: StepTooCoarse asks for at least ten
        dt=1e-4,
        torques={"rotor": ROTOR_TORQUE},
        speeds={"generator": GENERATOR_SPEED},
        initial_speeds={"rotor": ROTOR_SPEED},
    )
    return gearbox, res


def deflection_share(gearbox: pinwind.Gearbox, res: pinwind.Result, planet: str) -> float:
    """How far the rigid rows' geometry at the start is from the model's: e / a_w [-].

    The rows keep the working pressure angle of the working centre distance a_w; a planet's
    arms about its own centre and the sun's about its axis move with the centres by the
    deflections e of the planet's, its carrier's (lss) and its sun shaft's (iss) bearings.
    """
    e = sum(np.linalg.norm(res.bearing(b).displacement[0]) for b in (planet, "lss", "iss"))
    return e / gearbox.mesh("stage1_sun_planet1").centre_distance


def test_the_5mw_stage1_planets_start_with_equal_sun_and_ring_forces_carrying_the_sun_torque(
    rated_5mw,
):
    gearbox, res = rated_5mw
    sun_torque = ROTOR_TORQUE * Z_SUN / (Z_SUN + Z_RING)
    share = max(deflection_share(gearbox, res, f"stage1_planet{i}") for i in (1, 2, 3))
    # a few 1e-3: the rows hold the shafts with their own K_y, K_z (the iss shaft's carrier
    # rows IMS-PLC-A/B 6e7 N/m along u, Nejad et al. 2016 Table IX), softer than their mean
    assert share < 5e-3
    total = 0.0
    for i in (1, 2, 3):
        sun = res.mesh(f"stage1_sun_planet{i}").normal[0]
        assert_allclose(res.mesh(f"stage1_planet{i}_ring").normal[0], sun, rtol=share)
        total += sun
    # 829 kN each on average: T_sun / (3 r_b,sun).
    assert_allclose(total * R_B_SUN_1, sun_torque, rtol=share)


def test_the_5mw_at_rated_starts_with_no_acceleration_beyond_its_turning_deflections(rated_5mw):
    # A turning start cannot be exactly static: a sun deflected by its shaft's bearing load
    # (fixed in space: the weights, the next stage's tooth force) turns, relative to the carrier,
    # at the carrier's speed ω_c, so each planet's centre distance changes by e cos ω_c t and the
    # steady motion is periodic: the spins it couples accelerate by ω_c² e / r_b,sun, and the
    # faster shafts after them by that times their speed over the sun's. The largest such term
    # bounds every joint's acceleration at t = 0 (rad/s², and m/s² for the slides, whose own
    # term ω_c² e is smaller); the start without the rows' flanks had 425 rad/s² on a stage-1
    # planet.
    gearbox, res = rated_5mw
    hss_speed = abs(res.joint("hss").speed[0])
    bound = 0.0
    for carrier, sun_shaft, base_radius in (("lss", "iss", R_B_SUN_1), ("iss", "ims", R_B_SUN_2)):
        deflection = np.linalg.norm(res.bearing(sun_shaft).displacement[0])
        sun_speed = abs(res.joint(sun_shaft).speed[0])
        term = res.joint(carrier).speed[0] ** 2 * deflection / base_radius
        bound = max(bound, term * hss_speed / sun_speed)
    assert bound < 1.0
    acceleration = accelerations_at_start(res, gearbox)
    assert_allclose(acceleration, 0.0, rtol=0, atol=bound)
