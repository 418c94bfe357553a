"""Compliant gear meshes: closed forms of a compliant pair, the rigid limit, contact and backlash,
load sharing between planets, the energy the implicit scheme loses, and the coarse-step warning.

The pair is ``tests/conftest.two_gear_urdf``: 20/40 teeth, module 2 mm, 20°, no profile shift, at
the reference centre distance 60 mm; J_A = 0.0015 and J_B = 0.006 kg·m² about the shafts.
"""

from __future__ import annotations

import contextlib
import math
import warnings

import numpy as np
import pinocchio as pin
import pytest

import pinwind
from pinwind.analysis import load_sharing
from pinwind.dynamics.mesh import MeshSet
from pinwind.errors import EquilibriumNotReached, MalformedModel, PinwindWarning, StepTooCoarse
from pinwind.gears import GearPair
from pinwind.model.compliance import MeshCompliance
from pinwind.model.gearbox import loads
from tests.conftest import MODELS, two_gear_urdf

MODULE, ALPHA = 0.002, math.radians(20.0)
Z_A, Z_B = 20, 40
J_A, J_B = 0.0015, 0.006
R_BA = Z_A * MODULE * math.cos(ALPHA) / 2
R_BB = Z_B * MODULE * math.cos(ALPHA) / 2
BASE_PITCH = math.pi * MODULE * math.cos(ALPHA)


def _contact_ratio() -> float:
    """ε_α of the pair by hand: (√(r_a1² − r_b1²) + √(r_a2² − r_b2²) − a sin α) / p_b."""
    r_a1, r_a2 = Z_A * MODULE / 2 + MODULE, Z_B * MODULE / 2 + MODULE
    a = (Z_A + Z_B) * MODULE / 2
    length = math.sqrt(r_a1**2 - R_BA**2) + math.sqrt(r_a2**2 - R_BB**2) - a * math.sin(ALPHA)
    return length / BASE_PITCH


EPS = _contact_ratio()


def _pair():
    return loads(two_gear_urdf(), "pair.urdf")


def _constant(k_single: float, **kw) -> MeshCompliance:
    return MeshCompliance(stiffness=k_single, variation="constant", **kw)


def _mean_stiffness(k_single: float) -> float:
    """ISO 6336-1: c_γα = c′ (0.75 ε_α + 0.25)."""
    return k_single * (0.75 * EPS + 0.25)


def _peak_frequency(x: np.ndarray, dt: float) -> float:
    """Frequency of the largest spectral peak [Hz], interpolated between FFT bins."""
    x = (x - x.mean()) * np.hanning(len(x))
    n = 64 * len(x)
    spec = np.abs(np.fft.rfft(x, n))
    i = int(np.argmax(spec[1:])) + 1
    a, b, c = np.log(spec[i - 1 : i + 2])
    return (i + 0.5 * (a - c) / (a - 2 * b + c)) / (n * dt)


def test_static_deflection_is_force_over_stiffness_and_matches_the_gear_angles():
    gb = _pair()
    k1, torque = 1e8, 4.0
    res = pinwind.simulate(
        gb,
        duration=0.02,
        dt=2e-5,
        torques={"a": torque},
        speeds={"b": 0.0},
        gravity=np.zeros(3),
        meshes={"m": _constant(k1, damping_ratio=0.3)},
    )
    mesh = res.mesh("m")
    force = torque / R_BA
    np.testing.assert_allclose(mesh.normal[-1], force, rtol=1e-9)
    np.testing.assert_allclose(mesh.deflection[-1], force / _mean_stiffness(k1), rtol=1e-9)
    # The deflection comes from the positions: gear B is held, so δ = r_b,A θ_A.
    np.testing.assert_allclose(mesh.deflection[-1], R_BA * res.joint("a").angle[-1], rtol=1e-9)
    assert np.all(mesh.flank == 1.0)


@pytest.mark.parametrize("dt", [2e-5, 1e-5])
def test_free_vibration_frequency_is_the_closed_form_of_the_pair(dt):
    gb = _pair()
    k1, preload = 1e8, 1000.0
    # Balanced torques: the teeth carry `preload` at rest; starting undeflected, the pair swings
    # about that load at ω² = k (r_b,A²/J_A + r_b,B²/J_B) without losing contact.
    res = pinwind.simulate(
        gb,
        duration=0.1,
        dt=dt,
        torques={"a": preload * R_BA, "b": preload * R_BB},
        gravity=np.zeros(3),
        initial_deflection="none",
        meshes={"m": _constant(k1, damping=0.0)},
    )
    expected = math.sqrt(_mean_stiffness(k1) * (R_BA**2 / J_A + R_BB**2 / J_B)) / (2 * math.pi)
    measured = _peak_frequency(res.mesh("m").normal, dt)
    np.testing.assert_allclose(measured, expected, rtol=5e-3)
    assert res.mesh("m").normal.min() >= 0.0


def test_compliant_forces_converge_to_the_rigid_ones_as_one_over_stiffness():
    gb = _pair()
    omega, ramp = 2 * math.pi * 20, 0.02

    def torque(t):
        # A smooth start: little free vibration of the mesh mode beside the quasi-static error.
        return math.sin(0.5 * math.pi * min(t / ramp, 1.0)) ** 2 * (5.0 + 2.0 * math.sin(omega * t))

    run = dict(duration=0.1, dt=1e-5, torques={"a": torque}, speeds={"b": 0.0}, gravity=np.zeros(3))
    res = pinwind.simulate(gb, **run)
    rigid, time = res.mesh("m").normal, res.time
    late = slice(len(rigid) // 2, len(rigid) - 1)  # one period of the load, 0.05 … 0.1 s
    mass = J_A / R_BA**2  # gear a on its line of action (gear b is held) [kg]
    errors = []
    for k in (1e8, 1e9, 1e10):
        res = pinwind.simulate(gb, meshes={"m": _constant(k, damping=100.0)}, **run)
        deviation = res.mesh("m").normal[late] - rigid[late]
        errors.append(np.abs(deviation).max() / np.abs(rigid[late]).max())
        # Quasi-statically F = F_r − m δ̈, δ = F/k: F − F_r = −(m/k) F̈_r, with F_r = τ/R_b and
        # τ = 5 + 2 sin ωt: (m/k) 2ω²/R_b sin ωt, ten times smaller for a ten times stiffer mesh
        # (the damping enters at 1/k²). The start-up's free vibration (the mesh mode, kHz) keeps
        # no component at the load's 20 Hz over a whole period.
        in_phase = 2.0 * np.mean(deviation * np.sin(omega * time[late]))
        expected = mass / _mean_stiffness(k) * 2.0 * omega**2 / R_BA
        np.testing.assert_allclose(in_phase, expected, rtol=1e-3)
    assert errors[-1] < 1e-5


def _run_at_constant_speed(compliance: MeshCompliance, *, duration=0.2, dt=2e-5):
    gb = _pair()
    speed = 2 * math.pi * 200 / Z_A  # mesh frequency 200 Hz
    return pinwind.simulate(
        gb,
        duration=duration,
        dt=dt,
        speeds={"a": speed},
        torques={"b": 10.0},
        gravity=np.zeros(3),
        meshes={"m": compliance},
    ), speed


def test_time_varying_stiffness_puts_the_mesh_frequency_and_harmonics_in_the_spectra():
    # Stiff enough that the mesh mode (2.4 to 3.2 kHz) sits far above 200 Hz.
    res, speed = _run_at_constant_speed(MeshCompliance(stiffness=1e9, damping_ratio=0.1))
    dt, mesh = 2e-5, res.mesh("m")
    late = slice(len(res) // 4, None)
    mesh_frequency = Z_A * speed / (2 * math.pi)
    # Under a steady load the deflection follows the stiffness: it pulses once per tooth.
    np.testing.assert_allclose(
        _peak_frequency(mesh.deflection[late], dt), mesh_frequency, rtol=5e-3
    )
    # The force answers with the mesh frequency and its harmonics, and nothing between them.
    force = mesh.normal[late]
    spec = np.abs(np.fft.rfft((force - force.mean()) * np.hanning(len(force))))
    freqs = np.fft.rfftfreq(len(force), dt)
    floor = np.median(spec)
    # The first five harmonics (higher ones near the mesh mode leak wider than two bins).
    peaks = freqs[(spec > 50 * floor) & (freqs > 0) & (freqs < 5.5 * mesh_frequency)]
    harmonic = peaks / mesh_frequency
    assert len(peaks) > 0
    # Within the Hann window's main lobe (two bins) of a harmonic.
    bins = 2.01 * (freqs[1] - freqs[0]) / mesh_frequency
    np.testing.assert_allclose(harmonic, np.round(harmonic), atol=bins)
    assert spec[np.argmin(np.abs(freqs - mesh_frequency))] > 50 * floor


def test_two_pairs_are_in_contact_for_the_fraction_eps_minus_one():
    res, _ = _run_at_constant_speed(MeshCompliance(stiffness=1e8, damping_ratio=0.1))
    pairs = res.mesh("m").pairs
    np.testing.assert_allclose(np.mean(pairs == 2), EPS - 1.0, atol=0.01)
    assert set(np.unique(pairs)) == {1.0, 2.0}


def test_single_tooth_force_is_half_in_double_contact_and_whole_in_single_contact():
    res, _ = _run_at_constant_speed(MeshCompliance(stiffness=1e8, damping_ratio=0.1))
    mesh = res.mesh("m")
    two = mesh.pairs == 2
    # ISO shape: each of two pairs is 0.875 c′b, so they share equally; one pair takes all.
    np.testing.assert_allclose(mesh.single_tooth_force[two], mesh.normal[two] / 2, rtol=1e-12)
    np.testing.assert_allclose(mesh.single_tooth_force[~two], mesh.normal[~two], rtol=1e-12)


def test_deflection_stays_the_one_the_gear_angles_give_over_a_long_run():
    res, _ = _run_at_constant_speed(_constant(1e8, damping_ratio=0.1), duration=2.0, dt=2e-5)
    a, b = res.joint("a").angle, res.joint("b").angle
    # External pair on fixed axes: the front flank's overlap is r_b,A θ_A + r_b,B θ_B, modulo
    # one base pitch (a tooth pair further on).
    overlap = R_BA * a + R_BB * b
    overlap -= BASE_PITCH * np.round(overlap / BASE_PITCH)
    np.testing.assert_allclose(res.mesh("m").transmission_error, overlap, atol=1e-12 * BASE_PITCH)


def test_teeth_never_pull_and_fly_through_the_backlash_gap():
    gb = _pair()
    backlash, k1 = 1e-4, 1e8
    res = pinwind.simulate(
        gb,
        duration=0.2,
        dt=1e-5,
        # Gear A oscillates hard enough that light gear B leaves the flank and meets the other.
        speeds={"a": lambda t: 20.0 + 8.0 * math.sin(2 * math.pi * 30 * t)},
        torques={"b": 0.05},
        gravity=np.zeros(3),
        meshes={"m": _constant(k1, damping=0.0, backlash=backlash)},
    )
    mesh = res.mesh("m")
    assert mesh.normal.min() >= 0.0
    free = mesh.normal == 0.0
    assert free.any(), "the teeth never separated"
    back = (mesh.flank == -1.0) & ~free
    assert back.any(), "the back flank never took load"
    # Without damping the force over a step is k times the mean overlap of the loaded flank at
    # its start and end, both from the gear angles (θ = ½); free: neither flank overlaps.
    k = _mean_stiffness(k1)
    front = mesh.transmission_error  # δ_f from the angles
    mean_front = 0.5 * (front[:-1] + front[1:])
    mean_back = -mean_front - backlash
    on_front = (~free[:-1]) & (mesh.flank[:-1] == 1.0)
    on_back = back[:-1]
    scale = k * backlash
    np.testing.assert_allclose(
        mesh.normal[:-1][on_front], k * mean_front[on_front], atol=1e-9 * scale
    )
    np.testing.assert_allclose(mesh.normal[:-1][on_back], k * mean_back[on_back], atol=1e-9 * scale)
    assert np.all(mean_front[free[:-1]] <= 1e-12 * backlash)
    assert np.all(mean_back[free[:-1]] <= 1e-12 * backlash)


@pytest.mark.parametrize("rho", [1.0, 0.8])
def test_implicit_meshes_lose_the_energy_the_spectral_radius_sets(rho):
    # Released undeflected under the preload, the undamped pair swings about the static
    # deflection with vibration energy F²/(2 k). The ledger closes with the scheme's loss as its
    # own term, and that loss is what generalized-α's amplification leaves of the mode: none at
    # ρ∞ = 1 (the trapezoidal rule keeps a linear spring's energy), 1 − ρ(ωh)^(2N) of it after N
    # steps at ρ∞ < 1 (tests/dynamics/test_time_stepping.py derives ρ(ωh)).
    from pinwind.dynamics import Integrator
    from tests.dynamics.test_time_stepping import _spectral_radius

    gb = _pair()
    k1, preload = 1e8, 1000.0
    k_mean = _mean_stiffness(k1)
    omega = math.sqrt(k_mean * (R_BA**2 / J_A + R_BB**2 / J_B))
    vibration = preload**2 / (2 * k_mean)
    for dt in (1e-5, 5e-6):
        steps = round(2 * (2 * math.pi / omega) / dt)
        # ρ∞ < 1 damps the mesh mode numerically, as the run says; ρ∞ = 1 does not
        coarse = pytest.warns(StepTooCoarse) if rho < 1.0 else contextlib.nullcontext()
        with coarse:
            res = pinwind.simulate(
                gb,
                duration=steps * dt,
                dt=dt,
                torques={"a": preload * R_BA, "b": preload * R_BB},
                gravity=np.zeros(3),
                meshes={"m": _constant(k1, damping=0.0)},
                integrator=Integrator(rho_infinity=rho),
                initial_deflection="none",
            )
        e = res.energy
        balance = (
            e["kinetic"]
            - e["kinetic"][0]
            + e["potential_spring"]
            - e["potential_spring"][0]
            - (e["work_applied"] + e["work_drivers"] + e["work_gravity"] + e["work_constraints"])
            + e["dissipated"]
            + e["numerical"]
        )
        np.testing.assert_allclose(balance, 0.0, atol=1e-12 * e["work_applied"].max())
        expected = vibration * (1.0 - _spectral_radius(rho, omega * dt) ** (2 * steps))
        np.testing.assert_allclose(e["numerical"][-1], expected, rtol=0.05, atol=1e-9 * vibration)


def test_a_coarse_step_is_stable_and_warns_with_the_mesh_mode_and_a_resolving_step():
    gb = _pair()
    k1, preload = 1e8, 1000.0
    frequency = math.sqrt(_mean_stiffness(k1) * (R_BA**2 / J_A + R_BB**2 / J_B)) / (2 * math.pi)
    with pytest.warns(PinwindWarning, match=f"{frequency:.4g} Hz") as record:
        res = pinwind.simulate(
            gb,
            duration=0.2,
            dt=1e-3,
            torques={"a": preload * R_BA, "b": preload * R_BB},
            gravity=np.zeros(3),
            meshes={"m": _constant(k1, damping=0.0)},
        )
    assert f"dt ≤ {1 / (10 * frequency):.2g} s" in str(record[0].message)
    # Bounded: the mesh force stays within the undamped swing 0 … 2 × preload.
    assert res.mesh("m").normal.max() < 2.0 * preload * (1 + 1e-6)


def test_rigid_and_compliant_runs_report_the_same_outputs_under_the_same_names():
    gb = _pair()
    run = dict(duration=0.01, dt=1e-4, torques={"a": 1.0}, speeds={"b": 0.0})
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PinwindWarning)
        rigid = pinwind.simulate(gb, **run)
        compliant = pinwind.simulate(gb, meshes={"all": "compliant"}, **run)
    assert rigid.mesh_names == compliant.mesh_names
    for name in rigid.ARRAYS:
        assert getattr(rigid, name).shape == getattr(compliant, name).shape, name
    assert compliant.metadata["meshes"]["m"]["type"] == "compliant"
    assert rigid.metadata["meshes"]["m"]["type"] == "rigid"


def test_model_file_marks_a_mesh_compliant_with_its_values_in_file_units():
    text = two_gear_urdf().replace(
        '<mesh name="m" gear1="g1" gear2="g2"/>',
        '<mesh name="m" gear1="g1" gear2="g2" type="compliant" stiffness="2e8" '
        'damping="150" backlash_mm="0.1" stiffness_variation="constant"/>',
    )
    mesh = loads(text, "pair.urdf").meshes[0]
    assert mesh.compliance == MeshCompliance(
        stiffness=2e8, variation="constant", damping=150.0, backlash=1e-4
    )


@pytest.mark.parametrize(
    "attributes, words",
    [
        ('stiffness="2e8"', "only apply to a compliant mesh"),
        ('type="soft"', 'must be "rigid" or "compliant"'),
        ('type="compliant" backlash_mm="-0.1"', "backlash is -0.1 mm"),
        ('type="compliant" stiffness="-1"', "stiffness is -1 N/m"),
        ('type="compliant" pair_stiffness="0:1e8 x:2e8"', "pair_stiffness"),
    ],
)
def test_bad_mesh_compliance_in_the_file_is_refused_naming_the_mesh(attributes, words):
    text = two_gear_urdf().replace(
        '<mesh name="m" gear1="g1" gear2="g2"/>',
        f'<mesh name="m" gear1="g1" gear2="g2" {attributes}/>',
    )
    with pytest.raises(MalformedModel, match=r'<mesh name="m">') as err:
        loads(text, "pair.urdf")
    assert words in str(err.value)


# --- planet load sharing ------------------------------------------------------------------------


def _planetary_statics(gb, k_of, torque_sun, errors):
    """Planet loads of the Saleh stage held at the carrier, by hand: a linear stiffness network.

    Each mesh i is a spring k_i along its loaded flank's line of action n_i; its overlap is
    δ_i = −J_i Δq + n_i·(e_A − e_B) (J_i the rigid row, e the gear centres' position errors), and
    the sun and planets are in equilibrium: Σ k_i δ_i J_iᵀ + τ = 0 on their coordinates.
    """
    model = gb.model
    data = model.createData()
    q = gb.neutral()
    pin.computeJointJacobiansTimeVariation(model, data, q, np.zeros(model.nv))
    pin.forwardKinematics(model, data, q)
    ms = MeshSet(gb)
    rows = ms.evaluate(model, data)
    # Sun turning positively drives the planets (front flank); the planets, turning backwards,
    # drive the ring on their back flank.
    flank = np.array([1.0 if m.name.startswith("sun") else -1.0 for m in gb.meshes])
    jac, _ = ms.combine(rows, flank)
    normal = ms.line_of_action(rows, flank)
    carrier_axis = np.array([0.0, 0.0, 1.0])
    offsets = np.zeros(len(gb.meshes))
    for i, m in enumerate(gb.meshes):
        for gear, sign in ((m.gear_a, 1.0), (m.gear_b, -1.0)):
            if gear.name not in errors:
                continue
            centre = data.oMi[gear.joint_id].translation
            radial = centre - (centre @ carrier_axis) * carrier_axis
            radial /= np.linalg.norm(radial)
            tangential, radial_error = errors[gear.name]
            e = tangential * np.cross(carrier_axis, radial) + radial_error * radial
            offsets[i] += sign * normal[i] @ e
    free = [gb.v_index(j) for j in ("sun", "planet1", "planet2", "planet3")]
    k = np.array([k_of(m) for m in gb.meshes])
    jf = jac[:, free]
    tau = np.zeros(len(free))
    tau[0] = torque_sun
    dq = np.linalg.solve(jf.T @ (k[:, None] * jf), tau + jf.T @ (k * offsets))
    return k * (-jf @ dq + offsets)


def _saleh_compliant_run(errors):
    gb = pinwind.load(MODELS / "saleh2017_planetary.urdf")
    k1, torque_sun = 5e9, 1e5
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PinwindWarning)
        res = pinwind.simulate(
            gb,
            duration=0.03,
            dt=1e-5,
            torques={"sun": torque_sun},
            speeds={"carrier": 0.0},
            gravity=np.zeros(3),
            meshes={"all": _constant(k1, damping_ratio=0.3)},
            position_errors=errors,
        )

    def k_of(mesh):
        s, b = mesh.gear_a.spec, mesh.gear_b.spec
        path = GearPair(
            s.teeth,
            b.teeth,
            module=s.module,
            pressure_angle=s.pressure_angle,
            internal_1=s.internal,
            internal_2=b.internal,
            face_width=s.face_width,
        ).path_of_contact()
        return k1 * (0.75 * path.contact_ratio + 0.25)

    return gb, res, _planetary_statics(gb, k_of, torque_sun, errors)


def test_a_perfect_symmetric_stage_shares_the_load_exactly_equally():
    gb, res, expected = _saleh_compliant_run({})
    np.testing.assert_allclose(res.mesh_normal[-1], expected, rtol=1e-8)
    sharing = {s.gear: s for s in load_sharing(res, gb)}
    np.testing.assert_allclose(sharing["sun"].factor[-1], 1.0, atol=1e-9)
    np.testing.assert_allclose(sharing["ring"].factor[-1], 1.0, atol=1e-9)


def test_a_pin_error_shares_the_load_as_the_stiffness_network_says():
    errors = {"planet1": (10e-6, 0.0)}
    gb, res, expected = _saleh_compliant_run(errors)
    np.testing.assert_allclose(res.mesh_normal[-1], expected, rtol=1e-7)
    sun = {s.gear: s for s in load_sharing(res, gb)}["sun"]
    sun_forces = expected[:3]
    np.testing.assert_allclose(sun.factor[-1], sun_forces.max() / sun_forces.mean(), rtol=1e-7)
    # Planet 1 moved ahead of the sun's push (along the carrier's positive turn), so its teeth
    # meet the sun's later and it carries less than its share; the others carry more.
    assert res.mesh("sun_planet1").normal[-1] < sun_forces.mean()
    assert sun.factor[-1] > 1.01


def test_a_compliant_mesh_locked_by_rigid_ones_is_named_in_a_warning():
    gb = pinwind.load(MODELS / "saleh2017_planetary.urdf")
    with (
        pytest.warns(EquilibriumNotReached),
        pytest.warns(PinwindWarning, match='mesh "sun_planet1" is compliant, but the rigid'),
    ):
        res = pinwind.simulate(
            gb,
            duration=0.01,
            dt=1e-4,
            torques={"sun": 1e5},
            speeds={"carrier": 0.0},
            gravity=np.zeros(3),
            meshes={"sun_planet1": "compliant"},
        )
    # The rigid meshes carry the whole sun torque between the other two planets.
    np.testing.assert_allclose(res.mesh("sun_planet1").normal, 0.0, atol=1e-6)


@pytest.mark.parametrize("ring_first", [False, True])
def test_a_compliant_stage_settles_to_the_torque_balance_whichever_gear_is_written_first(
    ring_first,
):
    from tests.dynamics.test_planet_bearings import swapped_ring_meshes

    text = (MODELS / "saleh2017_planetary.urdf").read_text()
    gb = loads(swapped_ring_meshes(text) if ring_first else text, "saleh.urdf")
    torque_sun = 1e5
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PinwindWarning)
        res = pinwind.simulate(
            gb,
            duration=0.1,
            dt=1e-5,
            torques={"sun": torque_sun},
            speeds={"carrier": 0.0},
            gravity=np.zeros(3),
            meshes={"all": "compliant"},
        )
    # Sun and planets at rest: each of the six meshes carries T_sun / (3 r_b,sun).
    r_b_sun = 24 * 0.015 / 2 * math.cos(math.radians(24.5))
    np.testing.assert_allclose(res.mesh_normal[-1], torque_sun / (3 * r_b_sun), rtol=1e-7)
    assert np.all(res.mesh_deflection[-1] > 0.0)


def test_a_position_error_larger_than_the_module_is_refused_naming_the_gear():
    # 3 mm on g1, whose module is 2 mm (two_gear_urdf): its teeth would leave the mesh; 1e30 µm
    # (--position-error sun=1e30,0) ran without a word.
    from pinwind.errors import InputError

    pair = loads(two_gear_urdf(), path="pair.urdf")
    with pytest.raises(InputError) as info:
        pinwind.simulate(pair, duration=0.01, dt=1e-3, position_errors={"g1": (3e-3, 0.0)})
    assert str(info.value).startswith(
        'gear "g1": position error (tangential, radial) = (3000, 0) µm is more than its module 2 mm'
    )
