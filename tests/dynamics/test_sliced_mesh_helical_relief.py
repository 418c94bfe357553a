"""Helical slices with profile relief: each slice's pairs behind the relief at their own roll.

The pair is ``tests/conftest.two_gear_urdf`` (20/40 teeth, module 2 mm, face width b = 20 mm)
with β = ±10°. Slice s is a thin spur section at ζ_s from side I whose pairs sit at
q = y − ζ_s tan β_b along the transverse path g_α (y: the pair's front-section position), each
pair in [0, g_α] a spring k_ℓ/N, k_ℓ = c̄ p_bt/g_α, behind the gap the two gears' profile reliefs
leave at q. Written out here from the reliefs' amounts, lengths and shapes (ISO 21771's tip
relief, along the line of action): gear 1's tip relief C₁ (u/L₁)^n₁ with u = q − (g_α − L₁)
near E, gear 2's C₂ (u/L₂)^n₂ with u = L₂ − q near A (n = 1 linear, 2 parabolic).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

import pinwind
from pinwind.dynamics.integrator import Integrator
from pinwind.errors import InputError
from pinwind.model.compliance import MeshCompliance
from pinwind.model.gearbox import loads
from tests.conftest import two_gear_urdf

K = 1e8  # mean mesh stiffness c̄ [N/m]
B = 0.020  # face width [m]
TORQUE_B = 8.0  # brake on B [N·m]
C1, L1 = 3e-6, 0.004  # gear 1's tip relief: amount [m], roll length [m], linear
C2, L2 = 2e-6, 0.003  # gear 2's: parabolic


def helical_relieved(helix_deg: str = "10", *, shape_2: str = "parabolic") -> pinwind.Gearbox:
    """β = ±helix_deg at the reference centre distance m_t (z1 + z2)/2, both gears tip-relieved."""
    beta = math.radians(float(helix_deg))
    text = (
        two_gear_urdf(centre_distance=0.002 / math.cos(beta) * 30)
        .replace(
            '<gear name="g1" ',
            f'<gear name="g1" helix_angle_deg="{helix_deg}" tip_relief_um="{C1 * 1e6!r}" '
            f'tip_relief_length_mm="{L1 * 1e3!r}" ',
        )
        .replace(
            '<gear name="g2" ',
            f'<gear name="g2" helix_angle_deg="-{helix_deg}" tip_relief_um="{C2 * 1e6!r}" '
            f'tip_relief_length_mm="{L2 * 1e3!r}" relief_shape="{shape_2}" ',
        )
    )
    return loads(text, "helical_relieved.urdf")


def relief_gap(q: np.ndarray, g: float, power_2: int) -> np.ndarray:
    """The two tip reliefs' gap at roll position q from A [m] (module docstring), by hand."""
    into_1 = np.clip(q - (g - L1), 0.0, None) / L1
    into_2 = np.clip(L2 - q, 0.0, None) / L2
    return C1 * into_1 + C2 * into_2**power_2


def turning(gearbox, compliance: MeshCompliance, *, duration=0.02, dt=1e-5, rho=None):
    """A turning at 20 rad/s, balanced torques (ω_b/ω_a = −1/2)."""
    return pinwind.simulate(
        gearbox,
        duration=duration,
        dt=dt,
        initial_speeds={"a": 20.0},
        torques={"b": TORQUE_B, "a": TORQUE_B / 2},
        gravity=np.zeros(3),
        integrator=None if rho is None else Integrator(rho_infinity=rho),
        meshes={"m": compliance},
    )


def hand_energy(res, gearbox, n: int, power_2: int):
    """Σ_s Σ_j ½ (k_ℓ/N)(δ − e(q_s + j p_bt))₊² and Σ_s Σ_j (k_ℓ/N)(δ − e)₊ at the samples where
    the front flank carries, q_s = y − ζ_s tan β_b, δ the run's deflection at the face centre
    (no tilt, no lead gap: every slice's overlap). Also which samples have a pair short of
    contact behind its relief, and which have none within rounding of an end of g_α (there the
    pair count is ambiguous)."""
    path = gearbox.meshes[0].path
    g, p = path.length, path.base_pitch
    overlap = path.overlap_ratio * p  # Δ = b tan β_b
    mesh = res.mesh("m")
    front = (mesh.deflection > 0) & (mesh.flank > 0)
    delta = mesh.deflection[front]
    y = mesh.contact_position[front] - (path.start_roll_1 - 0.5 * overlap)
    zeta = (np.arange(n) + 0.5) * B / n
    q = y[:, None] - zeta[None, :] * overlap / B  # (samples, slices): the entering pairs
    line = K * p / g / n  # k_ℓ / N
    energy, force = np.zeros_like(delta), np.zeros_like(delta)
    relieved = np.zeros(delta.shape, dtype=bool)
    ambiguous = np.zeros(delta.shape, dtype=bool)
    for j in range(-1, 4):
        x = q + j * p
        inside = (x >= 0.0) & (x <= g)
        ambiguous |= np.any((np.abs(x) < 1e-9) | (np.abs(x - g) < 1e-9), axis=1)
        gap = relief_gap(x, g, power_2)
        reach = np.where(inside, np.clip(delta[:, None] - gap, 0.0, None), 0.0)
        energy += 0.5 * line * np.sum(reach**2, axis=1)
        force += line * np.sum(reach, axis=1)
        relieved |= np.any(inside & (gap > delta[:, None]), axis=1)
    return front, energy, force, relieved, ~ambiguous


def test_each_helical_slice_takes_the_relief_at_its_own_shifted_roll():
    """N = 6: the springs' energy at every sample is Σ_s Σ_j ½ (k_ℓ/N)(δ − e(q_s + j p_bt))₊²,
    q_s = y − ζ_s tan β_b, e the reliefs by hand: to 1e-12 with linear reliefs (the run's gap
    table is exact there). Gear 2's parabolic relief is a table of chords h = g_α/256 long in
    the run, within C₂ (h/L₂)²/8 of the parabola, which bounds the difference by F times that."""
    n = 6
    compliance = MeshCompliance(mean_stiffness=K, damping=0.0, slices=n, backlash=5e-5)
    for shape, power, exact in (("linear", 1, True), ("parabolic", 2, False)):
        gearbox = helical_relieved(shape_2=shape)
        res = turning(gearbox, compliance)
        front, energy, force, relieved, clear = hand_energy(res, gearbox, n, power)
        assert clear.sum() > 1000 and relieved[clear].sum() > 20  # pairs short of contact
        got = res.energy["potential_spring"][front]
        if exact:
            assert_allclose(got[clear], energy[clear], rtol=1e-12)
            continue
        h = gearbox.meshes[0].path.length / 256
        bound = force * C2 * (h / L2) ** 2 / 8 + 1e-12 * energy
        assert np.all(np.abs(got - energy)[clear] <= bound[clear])


def test_the_helical_relieved_slices_ledger_closes_and_rho_one_keeps_the_energy():
    """Undamped at ρ∞ = 1, 8 relieved helical slices: the pairs' stiffness and gaps moving with
    the roll put in the parametric work; what is left is the step's own loss. The pairs engaged
    are held over a step (as the single relieved line's), so each engagement change costs a
    little: measured 2.1e-5 of the peak potential at dt = 1e-5 s and 5.8e-6 at dt/2 (the single
    relieved spur line's 2.5e-6). It falls with the step, as a step's error does."""
    compliance = MeshCompliance(mean_stiffness=K, damping=0.0, slices=8, backlash=5e-5)
    losses = []
    for dt in (1e-5, 5e-6):
        res = turning(helical_relieved(), compliance, duration=0.05, dt=dt, rho=1.0)
        energy = res.energy
        scale = np.max(energy["potential_spring"])
        assert np.max(np.abs(energy["work_parametric"])) > 0.05 * scale
        assert np.max(np.abs(energy["dissipated"])) == 0.0
        losses.append(np.max(np.abs(energy["numerical"])) / scale)
    assert losses[0] < 5e-5
    assert losses[1] < losses[0] / 2


def test_flank_friction_on_helical_relieved_slices_is_booked_in_the_ledger():
    """μ = 0.05, undamped, ρ∞ = 1: the friction (the single line's, at the slices' load
    centre) takes 87 times the peak potential over 50 ms as friction_loss, and the ledger still
    closes to the step's own loss (measured 8.9e-6 of the peak potential)."""
    compliance = MeshCompliance(
        mean_stiffness=K, damping=0.0, slices=8, backlash=5e-5, friction_coefficient=0.05
    )
    res = turning(helical_relieved(), compliance, duration=0.05, rho=1.0)
    energy = res.energy
    scale = np.max(energy["potential_spring"])
    assert energy["friction_loss"][-1] > 10 * scale
    assert np.all(np.diff(energy["friction_loss"]) >= 0.0)
    assert np.max(np.abs(energy["numerical"])) < 5e-5 * scale


def test_helical_relieved_slices_at_a_vanishing_helix_angle_step_as_the_spur_slices():
    """β = 1e-12°: each slice's shift ζ_s tan β_b is below 1e-15 m, so with the same pair table
    (a user table, which a helical mesh takes as a spur one does) the helical relieved slices
    step as the spur relieved slices: to 1e-12 of the force over the first 1 ms (measured
    5e-15), then within 1e-10 (measured 2.4e-11), where a pair's engagement decided at a
    rounding-size overlap sends the two runs apart by rounding (the spur relieved slices' own
    bounds against one line)."""
    table = (np.array([0.0, 0.01]), np.array([0.6 * K, 0.9 * K]))
    compliance = MeshCompliance(pair_stiffness=table, damping_ratio=0.05, slices=5)
    spur = helical_relieved("0", shape_2="linear")
    helical = helical_relieved("1e-12", shape_2="linear")
    assert helical.meshes[0].path.overlap_ratio > 0.0 == spur.meshes[0].path.overlap_ratio
    one, other = (turning(gb, compliance) for gb in (spur, helical))
    a, h = one.mesh("m"), other.mesh("m")
    scale, defl = np.max(np.abs(a.normal)), np.max(np.abs(a.deflection))
    assert np.max(np.abs(one.energy["work_parametric"])) > 0.0
    for samples, tol in ((101, 1e-12), (None, 1e-10)):
        cut = slice(0, samples)
        for name in ("normal", "normal_front", "normal_back"):
            got, want = getattr(h, name)[cut], getattr(a, name)[cut]
            assert_allclose(got, want, rtol=0, atol=tol * scale)
        assert_allclose(h.deflection[cut], a.deflection[cut], rtol=0, atol=tol * defl)
        for term in ("potential_spring", "work_parametric"):
            e1, e2 = one.energy[term][cut], other.energy[term][cut]
            assert_allclose(e2, e1, rtol=0, atol=tol * np.max(np.abs(e1)))


def test_profile_relief_on_a_helical_mesh_of_one_contact_line_is_refused_with_the_fix():
    with pytest.raises(InputError, match='one contact line.*slices="8"'):
        turning(helical_relieved(), MeshCompliance(mean_stiffness=K), duration=0.001)
