"""Mesh phasing of planetary stages against closed forms derived by hand.

Every mesh's phase is read from a run's ``contact_position`` x (roll distance from gear A's
base-circle tangency point): φ = (x − x_C)/p_b, with x_C = r_b,A tan α_w the pitch point C and
p_b the base pitch, is a whole number whenever a tooth pair passes the pitch point, and advances
by one per mesh period. The lead of mesh i over mesh j is frac(σ (φ_i − φ_j)), σ = ±1 the
direction φ advances in: the fraction of a mesh period by which mesh i passes the same state
earlier. x_C, p_b and α_w are computed here from the gear data (ISO 21771), not taken from
pinwind.

Closed forms (derived here from the geometry; Parker & Lin, "Mesh phasing relationships in
planetary and epicyclic gears", J. Mech. Des. 126(2):365-370, 2004, state them with ± signs for
the two senses of rotation). Ring fixed, planet i at ψ_i about the sun axis (counter-clockwise
from planet 1), the sun turning positively relative to the carrier:

- sun-planet mesh i is the sun's tooth pattern passing a contact point that turns with the
  carrier, ψ_i ahead of planet 1's, so it lags planet 1's mesh by Z_s ψ_i/2π periods:
  lead γ_si = frac(−Z_s ψ_i/2π);
- ring-planet mesh i is the fixed ring's tooth pattern passing that point, met ψ_i/ω_c earlier:
  lead γ_ri = frac(Z_r ψ_i/2π). The assembly condition (Z_s + Z_r)/N whole makes γ_ri = γ_si;
- ring mesh against sun mesh of one planet: with the carrier driving and the sun braked, the
  sun mesh loads the planet flank facing its negative turn (flank −1 of the sun mesh) and the
  ring mesh the other one (flank +1, the planet is A), on pitch circles π apart. With the tooth
  centre at c, that flank is at c − ½ t_s τ on the sun mesh's working pitch circle and the other
  at c + ½ t_r τ on the ring mesh's (τ = 2π/Z_p, t the planet's tooth thickness there as a
  fraction of the circular pitch). The planet turns negatively relative to the carrier, so the
  ring mesh's pair passes its pitch point (t_s + t_r)/2 − Z_p/2 pitches after the sun mesh's:
  lead γ_rs = frac((Z_p − t_s − t_r)/2), with (ISO 21771)
  t = ½ + 2 x tan α/π + Z_p (inv α − inv α_w)/π. When the sun drives the planets instead, the
  loaded flanks face the other way relative to the planet's turn (the mirror image of the
  above, which leaves time as it is) and γ_rs = frac((Z_p + t_s + t_r)/2). Standard teeth
  (x = 0, α_w = α) have t_s = t_r = ½: γ_rs = 0 for an odd Z_p, ½ for an even one either way
  (Parker & Lin's parity rule).
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import pinwind
from pinwind.model.builders import planetary_urdf
from pinwind.model.gearbox import loads
from tests.conftest import MODELS

ALPHA = math.radians(20.0)
DTU = {"sun": 20, "planet": 35, "ring": 91, "x": (0.582, 0.419, -0.840), "module": 0.010}


def inv(angle: float) -> float:
    return math.tan(angle) - angle


def working_angle(z1: int, z2: int, x1: float, x2: float) -> float:
    """α_w from inv α_w = inv α + 2 tan α (x1 + x2)/(z1 + z2), internal z negative (ISO 21771)."""
    target = inv(ALPHA) + 2.0 * math.tan(ALPHA) * (x1 + x2) / (z1 + z2)
    lo, hi = 1e-6, 1.5
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if inv(mid) < target else (lo, mid)
    return 0.5 * (lo + hi)


def thickness(z: int, x: float, alpha_w: float) -> float:
    """Tooth thickness of an external gear on its working pitch circle / circular pitch there."""
    return 0.5 + 2.0 * x * math.tan(ALPHA) / math.pi + z * (inv(ALPHA) - inv(alpha_w)) / math.pi


def stage(sun: int, planet: int, ring: int, x=(0.0, 0.0, 0.0), module: float = 0.010):
    """Mesh geometry by hand: name → (r_b,A, x_C, p_b); the planet's working thicknesses."""
    a_sp = working_angle(sun, planet, x[0], x[1])
    a_pr = working_angle(planet, -ring, x[1], x[2])
    p_b = math.pi * module * math.cos(ALPHA)
    r_bs = sun * module * math.cos(ALPHA) / 2
    r_bp = planet * module * math.cos(ALPHA) / 2
    geometry = {}
    for i in (1, 2, 3):
        geometry[f"sun_planet{i}"] = (r_bs * math.tan(a_sp), p_b)
        geometry[f"planet{i}_ring"] = (r_bp * math.tan(a_pr), p_b)
    t_s = thickness(planet, x[1], a_sp)
    t_r = thickness(planet, x[1], a_pr)
    return geometry, t_s, t_r


CARRIER_DRIVES = ({"carrier": 1.5}, {"sun": -2e3})
SUN_DRIVES = ({"sun": -10.0}, {"carrier": 2e4})


def run_phases(gearbox, geometry, drive=CARRIER_DRIVES):
    """A run with all meshes compliant: mesh → (φ(t), flank(t)).

    ``drive``: (speeds, torques); by default the carrier at 1.5 rad/s with the sun braked.
    """
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the step does not resolve the mesh modes: not needed
        res = pinwind.simulate(
            gearbox,
            duration=0.15,
            dt=1e-4,
            speeds=drive[0],
            torques=drive[1],
            meshes={"all": "compliant"},
            gravity=np.zeros(3),
        )
    out = {}
    for name, (x_c, p_b) in geometry.items():
        m = res.mesh(name)
        k = len(res.time) // 3  # past the start
        out[name] = ((m.contact_position[k:] - x_c) / p_b, m.flank[k:])
    return out


def lead(phi_i: np.ndarray, phi_j: np.ndarray) -> float:
    """Lead of mesh i over mesh j in mesh periods, in [0, 1): a circular mean over the run."""
    advance = np.unwrap(2 * np.pi * phi_j) / (2 * np.pi)
    sigma = np.sign(advance[-1] - advance[0])
    mean = np.angle(np.mean(np.exp(2j * np.pi * sigma * (phi_i - phi_j)))) / (2 * np.pi)
    return mean % 1.0


def circular_gap(a: float, b: float) -> float:
    d = (a - b) % 1.0
    return min(d, 1.0 - d)


@pytest.fixture(scope="module")
def dtu_run():
    geometry, _, _ = stage(DTU["sun"], DTU["planet"], DTU["ring"], DTU["x"])
    return run_phases(pinwind.load(MODELS / "dtu500_planetary.urdf"), geometry)


def test_dtu500_ring_meshes_lead_planet_1_by_the_closed_form_as_the_sun_meshes_do(dtu_run):
    # DTU 500: Z_s/3 is not whole, so the planets are sequentially phased; planet i at
    # ψ_i = 120°·(i − 1) (models/dtu500_planetary.urdf, joint origins).
    for i in (2, 3):
        psi = 2.0 * math.pi * (i - 1) / 3
        ring = lead(dtu_run[f"planet{i}_ring"][0], dtu_run["planet1_ring"][0])
        sun = lead(dtu_run[f"sun_planet{i}"][0], dtu_run["sun_planet1"][0])
        expected_ring = (DTU["ring"] * psi / (2 * math.pi)) % 1.0  # 1/3, 2/3
        expected_sun = (-DTU["sun"] * psi / (2 * math.pi)) % 1.0
        assert circular_gap(ring, expected_ring) < 1e-3, (i, ring, expected_ring)
        assert circular_gap(sun, expected_sun) < 1e-3, (i, sun, expected_sun)


def test_dtu500_ring_mesh_leads_its_sun_mesh_by_the_profile_shifted_closed_form(dtu_run):
    _, t_s, t_r = stage(DTU["sun"], DTU["planet"], DTU["ring"], DTU["x"])
    expected = ((DTU["planet"] - t_s - t_r) / 2.0) % 1.0  # ≈ 0.0072, not 0.5 nor 0.0
    assert_ring_leads_sun(dtu_run, expected)


def assert_ring_leads_sun(phases, expected: float) -> None:
    """Each planet's ring mesh leads its sun mesh by ``expected`` mesh periods.

    On the flanks the derivation assumes: the sun mesh on its back flank, the ring mesh on its
    front flank (the planet's flank facing its positive turn).
    """
    for i in (1, 2, 3):
        phi_s, flank_s = phases[f"sun_planet{i}"]
        phi_r, flank_r = phases[f"planet{i}_ring"]
        assert np.all(flank_s == -1) and np.all(flank_r == 1)
        got = lead(phi_r, phi_s)
        assert circular_gap(got, expected) < 1e-3, (i, got, expected)


def test_dtu500_ring_mesh_leads_its_sun_mesh_the_other_way_when_the_sun_drives():
    # The sun driving (negatively here) with the carrier braked: the sun mesh loads the planet
    # flank facing against its turn relative to the carrier, the flank the derivation of the
    # module docstring takes when mirrored: the thicknesses enter with the other sign,
    # γ_rs = frac((Z_p + t_s + t_r)/2) ≈ 0.9928.
    geometry, t_s, t_r = stage(DTU["sun"], DTU["planet"], DTU["ring"], DTU["x"])
    gearbox = pinwind.load(MODELS / "dtu500_planetary.urdf")
    phases = run_phases(gearbox, geometry, SUN_DRIVES)
    assert_ring_leads_sun(phases, ((DTU["planet"] + t_s + t_r) / 2.0) % 1.0)


@pytest.mark.parametrize(
    "sun, planet, ring, expected",
    [(21, 27, 75, 0.0), (24, 30, 84, 0.5)],
    ids=["odd planet", "even planet"],
)
def test_ring_mesh_leads_its_sun_mesh_by_half_a_period_for_even_planets_only(
    sun, planet, ring, expected
):
    # Standard teeth: t_s = t_r = ½, γ_rs = frac((Z_p − 1)/2).
    text = planetary_urdf(
        sun=sun, planet=planet, ring=ring, planets=3, module=0.010,
        pressure_angle=ALPHA, face_width=0.1,
    )  # fmt: skip
    geometry, t_s, t_r = stage(sun, planet, ring)
    assert t_s == pytest.approx(0.5) and t_r == pytest.approx(0.5)
    assert ((planet - t_s - t_r) / 2.0) % 1.0 == pytest.approx(expected)
    phases = run_phases(loads(text, "stage.urdf"), geometry)
    for i in (1, 2, 3):
        got = lead(phases[f"planet{i}_ring"][0], phases[f"sun_planet{i}"][0])
        assert circular_gap(got, expected) < 1e-3, (i, got)


def test_an_explicit_tooth_phase_is_kept_and_the_other_planets_still_interlock():
    text = (MODELS / "dtu500_planetary.urdf").read_text()
    old = '<gear name="planet2" link="planet2" teeth="35"'
    assert old in text
    text = text.replace(old, old + ' tooth_phase_deg="10"')
    gearbox = loads(text, "dtu500_phased.urdf")
    geometry, _, _ = stage(DTU["sun"], DTU["planet"], DTU["ring"], DTU["x"])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = pinwind.simulate(
            gearbox,
            duration=1e-4,
            dt=1e-4,
            meshes={"all": "compliant"},
            gravity=np.zeros(3),
            # 1 N·m on the carrier presses the ring meshes' front flanks (unloaded, the flank
            # would be rounding's choice); its deflection, ~1e-10 m, is 1e-8 of a pitch.
            torques={"carrier": 1.0},
        )
    # In the reference pose: the flank of planet 2's tooth 0 facing its positive turn
    # (the ring mesh's front flank) crosses the ring mesh's working pitch circle at 10° from the
    # planet's x axis; the ring mesh's pitch point lies outwards, at 120°. The front flank's
    # pair is (10° − 120°)/(360°/Z_p) pitches past the pitch point.
    x_c, p_b = geometry["planet2_ring"]
    mesh = res.mesh("planet2_ring")
    assert mesh.flank[0] == 1
    got = ((mesh.contact_position[0] - x_c) / p_b) % 1.0
    expected = (DTU["planet"] * (10.0 - 120.0) / 360.0) % 1.0
    assert circular_gap(got, expected) < 1e-6, (got, expected)
    # Planet 3 is not set: its ring mesh still leads planet 1's by the closed form.
    phases = run_phases(gearbox, geometry)
    got = lead(phases["planet3_ring"][0], phases["planet1_ring"][0])
    expected = (DTU["ring"] * 2.0 / 3.0) % 1.0
    assert circular_gap(got, expected) < 1e-3, got


def test_equal_planets_without_position_errors_carry_equal_mean_loads():
    # Cyclic symmetry: with interlocking teeth every planet of the DTU stage sees the same
    # mesh-stiffness history, shifted by a third of a mesh period (γ_si above), so over many
    # mesh periods (about 50 here) the planets' mean mesh forces are equal. Gravity off, so
    # nothing else tells the planets apart. With the planets phased by their link frames the
    # means differed by 2-3 %.
    gearbox = pinwind.load(MODELS / "dtu500_planetary.urdf")
    carrier = 27.1 * 2 * math.pi / 60  # rad/s
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the step does not resolve the mesh modes: not needed
        res = pinwind.simulate(
            gearbox,
            duration=1.2,
            dt=5e-5,
            torques={"carrier": 500e3 / carrier},
            speeds={"sun": (1 + 91 / 20) * carrier},
            initial_speeds={"carrier": carrier},
            meshes={"all": "compliant"},
            gravity=np.zeros(3),
        )
    late = res.time >= 0.2  # past the start-up transient
    for kind in ("sun_planet{}", "planet{}_ring"):
        means = np.array([res.mesh(kind.format(i)).normal[late].mean() for i in (1, 2, 3)])
        np.testing.assert_allclose(means / means.mean(), 1.0, rtol=0, atol=5e-3, err_msg=kind)


def test_the_step_counts_the_pairs_in_contact_as_the_rating_does():
    # Two implementations of one count, in two languages: the compiled step's (cpp/mesh_path.hpp,
    # the mesh_pairs series) and gears.contact.pairs_in_contact (the ISO rating's). Over a turn
    # of the DTU stage they must agree at every sample of every mesh.
    import pinwind
    from pinwind.gears.contact import pairs_in_contact

    gb = pinwind.load(MODELS / "dtu500_planetary.urdf")
    res = pinwind.simulate(gb, duration=0.05, dt=1e-4, speeds={"carrier": 2.0}, torques={})
    for i, mesh in enumerate(gb.meshes):
        entering = res.mesh_contact_position[:, i] - mesh.path.start_roll_1
        assert {1.0, 2.0} <= set(res.mesh_pairs[:, i])  # single and double zones visited
        np.testing.assert_array_equal(
            res.mesh_pairs[:, i], pairs_in_contact(mesh.path, entering), err_msg=mesh.name
        )
