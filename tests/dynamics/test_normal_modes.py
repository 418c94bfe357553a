"""Natural modes of the linearised train (``modes/linearisation.py``, ``normal_modes.py``).

Closed forms, each derived here:

- the compliant pair of ``tests/conftest.two_gear_urdf``: one elastic mode, ω² = k (r_b,A²/J_A +
  r_b,B²/J_B) with k the mean mesh stiffness, ζ = c / (2 √(k m)), m = 1/(r_b,A²/J_A + r_b,B²/J_B);
  in it the gears turn against each other with J θ̇ ∝ r_b, so gear A holds the kinetic-energy
  share (r_b,A²/J_A) / (r_b,A²/J_A + r_b,B²/J_B); the mesh holds all the strain energy;
- two discs J on a torsional spring k: ω² = 2k/J;
- a planetary stage with identical, equally spaced planets and the sun held: the planets' own
  mode (planets turning against each other, carrier still) is (N − 1)-fold, N = 3;
- at an operating speed the velocity terms C(q, v) v add nothing on torsional coordinates: bodies
  turn about their own axes of symmetry, so M(q) is the same at every pose and every Christoffel
  symbol vanishes; a planet whose centre of mass is off its axis makes M depend on its angle, and
  then they act;
- a linear train released from rest under a step torque rings at its natural frequencies: the
  peaks of a mesh deflection's spectrum (Hann window, the peak's bin refined by a parabola
  through the log magnitudes of its neighbours, Δf/100 or better) are the modes' frequencies.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import pinwind
from pinwind.dynamics import Integrator
from pinwind.errors import SpeedOutOfRange, UnknownJoint
from pinwind.model.compliance import MeshCompliance
from pinwind.model.gearbox import loads
from pinwind.modes.linearisation import MAX_SPEED, linearise
from tests.conftest import two_gear_urdf
from tests.dynamics.test_time_stepping import (
    J_A,
    J_B,
    K_MESH,
    K_SINGLE,
    MASS,
    R_BA,
    R_BB,
    _free_pair,
    _frequency,
)
from tests.dynamics.test_torsional_spring import J, _shafts_urdf


def _pair_modes(damping: float = 0.0):
    gb = loads(two_gear_urdf(inertia_a=("0.002", "0.002", "0.003")), "pair.urdf")
    compliance = MeshCompliance(stiffness=K_SINGLE, variation="constant", damping=damping)
    return linearise(gb, meshes={"m": compliance}).modes()


def test_a_compliant_pair_has_one_elastic_mode_at_the_closed_form_frequency():
    j_a = 0.003
    modes = _pair_modes(damping=300.0)
    rigid, elastic = modes
    assert rigid.rigid and not elastic.rigid
    a, b = R_BA**2 / j_a, R_BB**2 / J_B
    omega = math.sqrt(K_MESH * (a + b))
    np.testing.assert_allclose(elastic.frequency, omega / (2 * math.pi), rtol=1e-12)
    np.testing.assert_allclose(
        elastic.damping_ratio, 300.0 / (2 * math.sqrt(K_MESH / (a + b))), rtol=1e-12
    )
    np.testing.assert_allclose(elastic.kinetic_share["a"], a / (a + b), rtol=1e-12)
    np.testing.assert_allclose(elastic.strain_share["m"], 1.0, rtol=1e-12)


def test_the_pair_mode_is_the_one_a_free_vibration_run_rings_at():
    gb = loads(two_gear_urdf(), "pair.urdf")
    compliance = MeshCompliance(stiffness=K_SINGLE, variation="constant", damping=0.0)
    (mode,) = [m for m in linearise(gb, meshes={"m": compliance}).modes() if not m.rigid]
    np.testing.assert_allclose(mode.frequency, math.sqrt(K_MESH / MASS) / (2 * math.pi), rtol=1e-12)
    # The same model released undeflected (the time-stepping tests' run), 200 steps per period:
    # the phase of (x, ẋ/ω) advances at the modal frequency.
    x, xdot, dt, _ = _free_pair(200, 10)
    np.testing.assert_allclose(_frequency(x, xdot, dt) / (2 * math.pi), mode.frequency, rtol=5e-3)
    assert J_A != J_B  # the closed form does not rest on equal inertias


def _spectral_peaks(x: np.ndarray, dt: float, count: int) -> list[float]:
    """Frequencies [Hz] of the ``count`` largest peaks of x's spectrum, lowest first."""
    magnitude = np.abs(np.fft.rfft((x - x.mean()) * np.hanning(len(x))))
    log = np.log(magnitude + 1e-300 * magnitude.max())
    peaks = [
        i
        for i in range(1, len(magnitude) - 1)
        if magnitude[i] > magnitude[i - 1] and magnitude[i] > magnitude[i + 1]
    ]
    peaks = sorted(peaks, key=lambda i: -magnitude[i])[:count]
    out = []
    for i in peaks:
        a, b, c = log[i - 1], log[i], log[i + 1]
        out.append((i + 0.5 * (a - c) / (a - 2 * b + c)) / (len(x) * dt))
    return sorted(out)


def test_the_pair_mode_is_the_peak_of_a_free_vibration_spectrum():
    gb = loads(two_gear_urdf(), "pair.urdf")
    compliance = MeshCompliance(stiffness=K_SINGLE, variation="constant", damping=0.0)
    (mode,) = [m for m in linearise(gb, meshes={"m": compliance}).modes() if not m.rigid]
    x, _, dt, _ = _free_pair(100, 200, integrator=Integrator(rho_infinity=1.0))
    (peak,) = _spectral_peaks(x, dt, 1)
    np.testing.assert_allclose(peak, math.sqrt(K_MESH / MASS) / (2 * math.pi), rtol=5e-3)
    np.testing.assert_allclose(peak, mode.frequency, rtol=5e-3)


@pytest.mark.filterwarnings("ignore::pinwind.errors.TorquesUnbalanced")
def test_three_modes_of_a_stage_are_the_peaks_of_a_free_vibration_spectrum():
    # The Saleh stage with constant, undamped mesh springs; a step torque on planet 1 alone
    # reaches every mode (the train also turns as a whole, which no mesh deflection sees).
    gb = pinwind.load("models/saleh2017_planetary.urdf")
    compliance = MeshCompliance(variation="constant", damping=0.0)
    modes = [m for m in linearise(gb, meshes={"all": compliance}).modes() if not m.rigid]
    expected = sorted({round(m.frequency, 6) for m in modes})
    assert len(expected) == 3  # two rotational modes and the double planet mode
    dt = 5e-6  # ≥ 100 steps per period of the highest mode (1.9 kHz)
    res = pinwind.simulate(
        gb,
        duration=0.2,
        dt=dt,
        torques={"planet1": 1e4},
        gravity=np.zeros(3),
        initial_deflection="none",
        meshes={"all": compliance},
        integrator=Integrator(rho_infinity=1.0),
    )
    peaks = _spectral_peaks(res.mesh("sun_planet1").transmission_error, dt, 3)
    np.testing.assert_allclose(peaks, expected, rtol=5e-3)


def test_two_discs_on_a_torsional_spring_ring_at_root_two_k_over_j():
    k = 800.0
    gb = loads(_shafts_urdf(stiffness=k), "shafts.urdf")
    (mode,) = [m for m in linearise(gb).modes() if not m.rigid]
    np.testing.assert_allclose(mode.frequency, math.sqrt(2 * k / J) / (2 * math.pi), rtol=1e-12)
    np.testing.assert_allclose(mode.kinetic_share["a"], 0.5, rtol=1e-12)


def test_bearing_and_spring_dampers_give_the_modal_damping_ratio_by_hand():
    # Mode φ = (1, −1)/√(2J) (mass-normalised): a dashpot c_b on bearing a alone gives
    # φᵀCφ = c_b/(2J), the spring's c_s on the twist (e_a − e_b) gives 2 c_s/J; ζ = φᵀCφ/(2ω).
    k, c_b, c_s = 800.0, 0.3, 0.1
    gb = loads(_shafts_urdf(stiffness=k, bearing_damping=c_b, spring_damping=c_s), "shafts.urdf")
    (mode,) = [m for m in linearise(gb).modes() if not m.rigid]
    omega = math.sqrt(2 * k / J)
    expected = (c_b / (2 * J) + 2 * c_s / J) / (2 * omega)
    np.testing.assert_allclose(mode.damping_ratio, expected, rtol=1e-12)


def test_identical_planets_have_a_planet_mode_of_multiplicity_n_minus_one():
    gb = pinwind.load("models/dtu500_planetary.urdf")
    modes = linearise(gb, meshes={"all": "compliant"}, held=["sun"]).modes()
    frequencies = np.array([m.frequency for m in modes])
    pairs = [(i, j) for i in range(len(modes)) for j in range(i + 1, len(modes))
             if math.isclose(frequencies[i], frequencies[j], rel_tol=1e-9)]  # fmt: skip
    assert len(pairs) == 1  # one double mode, N − 1 = 2
    for i in pairs[0]:
        shares = modes[i].kinetic_share
        assert abs(shares["carrier"]) < 1e-9 and abs(shares["sun"]) < 1e-9


def test_a_held_joint_the_model_does_not_have_is_refused_naming_the_joints():
    gb = loads(two_gear_urdf(), "pair.urdf")
    with pytest.raises(UnknownJoint, match='unknown joint "generator"'):
        linearise(gb, held=["generator"])


def test_at_speed_the_torsional_coordinates_feel_no_gyroscopic_or_centrifugal_terms():
    gb = pinwind.load("models/cart600_gearbox.urdf")
    # Why: the inertia matrix does not depend on the pose (seeded random poses).
    data = gb.model.createData()
    at_rest = pin.crba(gb.model, data, gb.neutral()).copy()
    for q in np.random.default_rng(7).uniform(-np.pi, np.pi, (5, gb.model.nq)):
        np.testing.assert_allclose(pin.crba(gb.model, data, q), at_rest, atol=1e-9)
    omega = 2.0  # rad/s on the carrier
    lin = linearise(gb, meshes={"all": "compliant"}, speeds={"carrier": omega})
    fastest = np.abs(lin.speed).max()
    assert fastest > omega  # the output shafts turn faster
    scale = np.abs(lin.mass).max()
    np.testing.assert_allclose(lin.gyroscopic, 0.0, atol=1e-12 * scale * fastest)
    np.testing.assert_allclose(lin.centrifugal, 0.0, atol=1e-12 * scale * fastest**2)
    rest = linearise(gb, meshes={"all": "compliant"}).modes()
    np.testing.assert_allclose(
        [m.frequency for m in lin.modes()], [m.frequency for m in rest], rtol=1e-12
    )


def test_modes_at_speed_of_an_unbalanced_planet_are_refused_naming_it():
    # Planet 1's centre of mass 50 mm off its axis, the carrier at 40 rad/s: the centrifugal
    # stiffness m e r Ω² ≈ 1113 kg · 0.05 m · 0.54 m · 1600 /s² ≈ 5e4 N·m/rad is above 1e-6 of
    # the stiffness scale (the largest entry of K, ≈ 2e10 N·m/rad on the ring's meshes): it
    # would move the frequencies in their printed digits.
    text = Path("models/saleh2017_planetary.urdf").read_text()
    link = text.index('<link name="planet1">')
    origin = text.index('<origin xyz="0 0 0"', link)
    text = text[:origin] + '<origin xyz="0.05 0 0"' + text[origin + len('<origin xyz="0 0 0"') :]
    gb = loads(text, "unbalanced.urdf")
    meshes = {"all": "compliant"}
    assert linearise(gb, meshes=meshes).modes()  # at rest the velocity terms are zero
    with pytest.raises(SpeedOutOfRange, match="act on .*planet1.*linearise at speed 0"):
        linearise(gb, meshes=meshes, speeds={"carrier": 40.0}).modes()


@pytest.mark.parametrize(
    ("speed", "message"),
    [(-1.0, "give 0 or more"), (math.nan, "give 0 or more"), (MAX_SPEED, "beyond the 1e\\+05")],
)
def test_a_speed_outside_the_linearisation_s_range_is_refused(speed, message):
    gb = pinwind.load("models/saleh2017_planetary.urdf")
    with pytest.raises(SpeedOutOfRange, match=message):
        linearise(gb, speeds={"carrier": speed})


def test_the_speed_bound_is_the_one_a_run_calls_diverged():
    from pinwind.dynamics.simulate import MAX_PLAUSIBLE_SPEED

    assert MAX_SPEED == MAX_PLAUSIBLE_SPEED
