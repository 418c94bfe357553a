"""Per-tooth stress histories and damage: teeth passes = relative revolutions × meshes."""

from __future__ import annotations

import math

import numpy as np
import pytest

import pinwind
from pinwind.errors import InputError, TorquesUnbalanced
from pinwind.gears.gear_pair import GearPair
from pinwind.gears.rating_iso import form_factors
from pinwind.life.root_stress import ISO_ROOT_STRESS
from pinwind.life.sn_curve import SNCurve
from pinwind.life.tooth_damage import (
    ToothContacts,
    entering_teeth,
    gear_tooth_damage,
    histories_damage,
    mesh_teeth,
    tooth_histories,
)
from pinwind.model.compliance import MeshCompliance
from pinwind.model.gearbox import loads
from tests.conftest import MODELS, two_gear_urdf

#: N(s) = (1000 MPa / s)³: 100 MPa fails in 10³ cycles.
ROUND = SNCurve(reference_stress=1000e6, slope_exponent=3.0)


def synthetic_mesh(*, teeth: int, revolutions: int, first_tooth: int, load: float):
    """A gear rolling forward at a constant rate through one mesh of contact ratio 1.5, base
    pitch 1 (unit roll), 40 samples per pitch, from X = 0.6 to X = 0.6 + revolutions · z − 1.

    Tooth k enters at X = k (its entering pair at x = X − k ∈ [0, 1)); with x < 0.5 the pair
    ahead, at x + 1 ≤ 1.5, is still in contact and the two share the load. So each pass is a
    hump 0 → load/2 → load → load/2 → 0. Starting at x = 0.6 (one pair, tooth 0 in mid-pass)
    and stopping one pitch short of the last whole turn, every tooth makes ``revolutions``
    passes with the full load in each (the first of tooth 0 and the last of tooth z − 1 cut
    but past their single-pair zone)."""
    roll = np.arange(0.6, 0.6 + revolutions * teeth - 1.0, 1.0 / 40.0)
    x = roll % 1.0
    pairs = np.where(x < 0.5, 2, 1)
    tooth = entering_teeth(x, base_pitch=1.0, teeth=teeth, first_tooth=first_tooth)
    contacts = ToothContacts(
        tooth=tooth,
        leading_tooth=(tooth - 1) % teeth,
        entering=np.where(pairs == 2, load / 2, load),
        leading=np.full(x.size, load / 2),
        pairs=pairs,
    )
    return contacts


def test_entering_tooth_advances_once_per_base_pitch_and_goes_back_when_turning_back():
    """Roll 0 → 2.5 pitches → 1.2: teeth 0, 1, 2 enter, then the gear turns back past 2 and
    tooth 1 is the entering one again; counted from tooth 5 of 7, wrapping past 6."""
    roll = np.concatenate([np.linspace(0.0, 2.5, 26), np.linspace(2.4, 1.2, 13)])
    teeth = entering_teeth(roll % 1.0, base_pitch=1.0, teeth=7, first_tooth=5)
    np.testing.assert_array_equal(teeth, (5 + np.floor(roll + 1e-9).astype(int)) % 7)


def test_constant_load_gives_each_tooth_revolutions_times_meshes_cycles():
    """A sun of 21 teeth meeting 3 planets a third of a turn apart (first teeth 0, 7, 14) for
    4 relative revolutions: each tooth passes 4 × 3 = 12 times, one cycle of range F each."""
    teeth, revolutions, load = 21, 4, 100e6
    contacts = [
        synthetic_mesh(teeth=teeth, revolutions=revolutions, first_tooth=f, load=load)
        for f in (0, 7, 14)
    ]
    histories = tooth_histories(contacts, teeth=teeth)
    damage = histories_damage(histories, gear="sun", curve=ROUND, time_factor=1.0)
    np.testing.assert_allclose(damage.cycle_counts, revolutions * 3, rtol=0, atol=0)
    np.testing.assert_allclose(damage.peak_stress, load, rtol=0, atol=0)
    # 12 cycles at 100 MPa, 1000 cycles to failure each.
    np.testing.assert_allclose(damage.damage, 12 / 1000, rtol=1e-12)


def test_time_factor_scales_every_tooths_damage():
    contacts = [synthetic_mesh(teeth=10, revolutions=2, first_tooth=0, load=100e6)]
    damage = histories_damage(
        tooth_histories(contacts, teeth=10), gear="g", curve=ROUND, time_factor=3600.0
    )
    np.testing.assert_allclose(damage.damage, 2 * 3600 / 1000, rtol=1e-12)


def test_heaviest_loaded_tooth_is_the_worst():
    """Tooth 3 of 10 carries twice the load on its pass of the second turn: its damage is
    1 + 2³ = 9 units where the others have 2 (N ∝ s⁻³)."""
    contacts = synthetic_mesh(teeth=10, revolutions=2, first_tooth=0, load=100e6)
    heavy = (contacts.tooth == 3) & (np.arange(contacts.tooth.size) > 10 * 40)
    doubled = ToothContacts(
        tooth=contacts.tooth,
        leading_tooth=contacts.leading_tooth,
        entering=np.where(heavy, 2.0, 1.0) * contacts.entering,
        leading=contacts.leading,
        pairs=contacts.pairs,
    )
    damage = histories_damage(
        tooth_histories([doubled], teeth=10), gear="g", curve=ROUND, time_factor=1.0
    )
    assert damage.worst_tooth == 3
    unit = 1 / 1000
    np.testing.assert_allclose(damage.worst, 9 * unit, rtol=1e-12)
    np.testing.assert_allclose(np.delete(damage.damage, 3), 2 * unit, rtol=1e-12)


def test_three_pairs_in_contact_raise():
    contacts = synthetic_mesh(teeth=10, revolutions=1, first_tooth=0, load=1.0)
    three = ToothContacts(
        contacts.tooth,
        contacts.leading_tooth,
        contacts.entering,
        contacts.leading,
        contacts.pairs + 1,
    )
    with pytest.raises(InputError, match="contact ratio below 2"):
        tooth_histories([three], teeth=10)


def test_compliant_pair_at_constant_speed_gives_one_cycle_per_tooth_pass():
    """The 20/40 test pair (module 2 mm, 20 mm wide) driven at a 200 Hz mesh frequency against
    10 N·m for 0.15 s: 200 · 0.15 = 30 tooth pairs enter, each one pinion and one wheel tooth.
    Every pass is one cycle of nearly the largest stress (the pair's load rises and falls once),
    so each gear's teeth count 30 such cycles, ± 2 for the passes cut at the ends; a pinion
    tooth passes 1.5 times on average (1 or 2), a wheel tooth 0.75 times (0 or 1)."""
    gearbox = loads(two_gear_urdf(), "pair.urdf")
    result = pinwind.simulate(
        gearbox,
        duration=0.15,
        dt=2e-5,
        speeds={"a": 2 * math.pi * 200 / 20},
        torques={"b": 10.0},
        gravity=np.zeros(3),
        meshes={"m": MeshCompliance(stiffness=1e9, damping_ratio=0.1)},
    )
    # Tooth j + 1 sits a pitch ahead of tooth j in the positive sense: the pinion, turning
    # positively, brings tooth j − 1 in next; the wheel turns the other way.
    for gear, teeth, step in (("g1", 20, -1), ("g2", 40, 1)):
        changes = np.diff(mesh_teeth(result, gearbox, "m", gear).tooth)
        np.testing.assert_array_equal(np.unique(changes % teeth), [0, step % teeth])
    curve = SNCurve(reference_stress=10e9, slope_exponent=3.0)
    for gear, teeth, most in (("g1", 20, 2), ("g2", 40, 1)):
        (damage,) = gear_tooth_damage(result, gearbox, gear, curve=curve, time_factor=1.0)
        threshold = 0.5 * damage.peak_stress.max()
        passes = np.array([np.sum(c.counts[c.ranges > threshold]) for c in damage.cycles])
        assert passes.shape == (teeth,)
        assert 28 <= passes.sum() <= 32, passes
        assert passes.min() >= most - 1 and passes.max() <= most, passes


def test_root_stress_histories_peak_at_the_largest_tooth_force_times_iso_factors():
    """The 20/40 pair against 10 N·m: each gear's largest root stress is the largest force a
    tooth pair carries times ISO 6336-3's cos α/(b m) Y_F Y_S of that gear (b = 20 mm,
    m = 2 mm), and each pass of a tooth is one large root cycle, as for the contact (the small
    cycles within a pass differ: the root stress goes as F, the contact stress as √F)."""
    gearbox = loads(two_gear_urdf(), "pair.urdf")
    result = pinwind.simulate(
        gearbox,
        duration=0.05,
        dt=2e-5,
        speeds={"a": 2 * math.pi * 200 / 20},
        torques={"b": 10.0},
        gravity=np.zeros(3),
        meshes={"m": MeshCompliance(stiffness=1e9, damping_ratio=0.1)},
    )
    single = np.abs(result.mesh_single_tooth_force[:, 0])
    leading = np.where(result.mesh_pairs[:, 0] == 2, np.abs(result.mesh_normal[:, 0]) - single, 0)
    largest = float(np.max(np.maximum(single, leading)))
    mesh = gearbox.meshes[0]
    pair = GearPair.from_gears(mesh.gear_a.spec, mesh.gear_b.spec)
    curve = SNCurve(reference_stress=10e9, slope_exponent=3.0)
    for gear, index in (("g1", 1), ("g2", 2)):
        y_f, y_s = form_factors(pair, index)
        (root,) = gear_tooth_damage(
            result, gearbox, gear, curve=curve, time_factor=1.0, root_stress=ISO_ROOT_STRESS
        )
        (contact,) = gear_tooth_damage(result, gearbox, gear, curve=curve, time_factor=1.0)
        np.testing.assert_allclose(
            root.peak_stress.max(),
            largest * math.cos(math.radians(20.0)) / (0.020 * 0.002) * y_f * y_s,
            rtol=1e-9,
        )
        passes = [
            [np.sum(c.counts[c.ranges > 0.5 * d.peak_stress.max()]) for c in d.cycles]
            for d in (root, contact)
        ]
        np.testing.assert_array_equal(passes[0], passes[1])


def test_gear_without_a_mesh_raises():
    gearbox = loads(two_gear_urdf(), "pair.urdf")
    with pytest.warns(TorquesUnbalanced):
        result = pinwind.simulate(gearbox, duration=1e-3, dt=1e-4, torques={"a": 1.0})
    with pytest.raises(InputError, match="g1, g2"):
        gear_tooth_damage(result, gearbox, "g3", curve=ROUND, time_factor=1.0)


@pytest.fixture(scope="module")
def dtu_run():
    """The DTU stage (sun 20, planets 35, ring 91; Jørgensen 2014) with rigid meshes, carrier
    driven at 2 rad/s against a sun torque: each planet turns 91/35 · 2 = 5.2 rad/s on the
    carrier."""
    gearbox = pinwind.load(MODELS / "dtu500_planetary.urdf")
    result = pinwind.simulate(
        gearbox, duration=1.5, dt=1e-4, speeds={"carrier": 2.0}, torques={"sun": -2000.0}
    )
    return gearbox, result


def test_sun_and_ring_teeth_at_the_three_planets_are_a_third_of_a_turn_apart(dtu_run):
    """Planets 120° apart meet sun teeth 20/3 = 6.7 apart and ring teeth 91/3 = 30.3 apart
    (the nearest whole teeth, either side), all on one flank of each gear."""
    gearbox, result = dtu_run
    for gear, meshes, teeth in (
        ("sun", ("sun_planet1", "sun_planet2", "sun_planet3"), 20),
        ("ring", ("planet1_ring", "planet2_ring", "planet3_ring"), 91),
    ):
        found = [mesh_teeth(result, gearbox, mesh, gear) for mesh in meshes]
        first = [int(f.tooth[0]) for f in found]
        for k, f in ((1, first[1]), (2, first[2])):
            gap = (f - first[0]) % teeth
            assert math.floor(k * teeth / 3) - 1 <= gap <= math.ceil(k * teeth / 3) + 1, first
        assert len({int(x) for f in found for x in np.unique(f.flank)}) == 1


def test_planet_teeth_meet_the_sun_and_the_ring_half_a_turn_apart_on_opposite_flanks(dtu_run):
    """A planet's sun and ring contacts lie on opposite sides of its centre, so a tooth that
    enters the sun mesh enters the ring mesh about half a turn on the carrier later or earlier:
    π / 5.2 rad/s = 0.604 s, to within one mesh period 2π / (35 · 5.2) = 0.035 s (the two
    paths of contact are not exactly opposite); its number there is 35/2 = 17.5 ± 1.5 away.
    Pushing on the sun side and on the ring side, the two meshes load opposite flanks."""
    gearbox, result = dtu_run
    sun = mesh_teeth(result, gearbox, "sun_planet1", "planet1")
    ring = mesh_teeth(result, gearbox, "planet1_ring", "planet1")
    assert int(np.unique(sun.flank)[0]) == -int(np.unique(ring.flank)[0])
    assert 16 <= (int(ring.tooth[0]) - int(sun.tooth[0])) % 35 <= 19
    half_turn, period = math.pi / 5.2, 2 * math.pi / (35 * 5.2)

    def entries(tooth: np.ndarray) -> dict[int, float]:
        changed = np.flatnonzero(np.diff(tooth) != 0) + 1
        return {int(tooth[k]): float(result.time[k]) for k in changed}

    at_sun, at_ring = entries(sun.tooth), entries(ring.tooth)
    common = sorted(set(at_sun) & set(at_ring))
    assert len(common) >= 10
    delays = np.abs([at_ring[j] - at_sun[j] for j in common])
    np.testing.assert_allclose(delays, half_turn, rtol=0, atol=period)


def test_samples_that_skip_half_a_base_pitch_are_refused_with_the_rate_that_follows_the_roll():
    """At a 200 Hz mesh frequency a base pitch rolls by in 5 ms: samples 3 ms apart cannot tell
    the tooth entering from the one before; 1 ms apart they can (0.2 base pitches)."""
    gearbox = loads(two_gear_urdf(), "pair.urdf")
    run = dict(
        duration=0.06, dt=2e-5, speeds={"a": 2 * math.pi * 200 / 20}, torques={"b": 10.0},
        gravity=np.zeros(3), meshes={"m": MeshCompliance(stiffness=1e9, damping_ratio=0.1)},
    )  # fmt: skip
    coarse = pinwind.simulate(gearbox, keep=150, **run)
    # 3 ms at 200 Hz: 0.6 base pitches; twice the mesh frequency, 400 Hz, follows it.
    with pytest.raises(InputError, match=r"roll 0\.60 base pitches.*at least 400 Hz"):
        mesh_teeth(coarse, gearbox, "m", "g1")
    fine = pinwind.simulate(gearbox, keep=50, **run)
    assert len(np.unique(mesh_teeth(fine, gearbox, "m", "g1").tooth)) >= 10
